#version 450 core
// A point emitter's disc (emitter_glow.glsl), drawn as a round point of its projected size;
// one smaller than a pixel as a point of one pixel. With LISTED, the emitters
// point_glow.comp listed as larger than a pixel, one point each.
#include "common.glsl"
#include "emitter.glsl"
#include "emitter_glow.glsl"
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
#ifdef LISTED
layout(std430, binding = 1) readonly buffer Discs { uint disc_command[5]; uint discs[]; };
#endif
uniform mat4 view_projection;
out vec3 glow_radiance_out;  // of the disc, or of the one pixel
out float glow_radius_out;   // in pixels

void main() {
#ifdef LISTED
    Emitter e = emitters[discs[gl_VertexID]];
#else
    Emitter e = emitters[gl_VertexID];
#endif
    glow_radius_out = glow_radius(e);
    glow_radiance_out = glow_radiance(e, glow_radius_out);
    gl_Position = e.position.w > 0.0 ? view_projection * vec4(e.position.xyz, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
    gl_PointSize = glow_radius_out < 0.5 ? 1.0 : ceil(2.0 * glow_radius_out + 1.0);
}
