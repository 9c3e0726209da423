#version 450 core
// The Warp Status pass, one warped light at a time: per pixel, the status of the texel of
// the light's warped map that looks toward the pixel's surface, kept when worse than what
// an earlier light left (alpha holds the code: 0 no warped map sees the pixel, 1 converged,
// 2 approximate, 3 failed, 4 missed: the texel found no geometry though the camera sees a
// surface in its direction).
#include "gbuffer.glsl"
#include "rsm_lookup.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform image2D status_pass;
uniform isampler2D warp_status;
uniform vec3 status_colours[5];

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(status_pass)))) return;
    vec3 p, n, albedo;
    int face;
    ivec2 texel;
    if (!gbuffer_surface(pixel, p, n, albedo) || !rsm_face_texel(p, face, texel)) return;
    int status = texelFetch(warp_status, lookup_origin[face] + texel, 0).r & 3;
    int code = status == 0 ? 4 : status;
    vec4 previous = imageLoad(status_pass, pixel);
    if (float(code) > previous.a) imageStore(status_pass, pixel, vec4(status_colours[code], float(code)));
}
