#version 450 core
// The tint of what is seen or lit through transmitting surfaces: drawn after the opaque
// pass, behind its depth and not writing it, multiplied into the colour attachments
// (blend DST_COLOR, ZERO): the tint into attachment TINT_ATTACHMENT, 1 (no change) into
// the others (the G-buffer's tint image: 0; a light's map: its flux, 2, and with TINT_MAP
// its tint, 3).
#include "surface.glsl"
#include "surface_vertices.glsl"
layout(location = 0) out vec4 out_0;
#if TINT_ATTACHMENT == 2
layout(location = 1) out vec4 out_1;
layout(location = 2) out vec4 out_2;
#endif
#ifdef TINT_MAP
layout(location = 3) out vec4 out_3;
#endif

void main() {
    vec3 tint;
    if (!surface_passing_tint(surface_vec4(VERTEX_ALBEDO), surface_point(), surface_vec4(VERTEX_TINT),
                              gl_FragCoord.xy, tint)) discard;
#if TINT_ATTACHMENT == 2
    out_0 = vec4(1.0);
    out_1 = vec4(1.0);
    out_2 = vec4(tint, 1.0);
#ifdef TINT_MAP
    out_3 = vec4(tint, 1.0);
#endif
#else
    out_0 = vec4(tint, 1.0);
#endif
}
