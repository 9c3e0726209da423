#version 450 core
// A point emitter's disc (emitter_glow.glsl), drawn as a round point of its projected size:
// the emitters point_glow.comp listed as wider than it adds itself, one point each.
#include "common.glsl"
#include "emitter.glsl"
#include "emitter_glow.glsl"
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 1) readonly buffer Discs { uint disc_command[5]; uint discs[]; };
uniform mat4 view_projection;
out vec3 glow_radiance_out;
out float glow_radius_out;   // in pixels

void main() {
    Emitter e = emitters[discs[gl_VertexID]];
    glow_radius_out = glow_radius(e);
    glow_radiance_out = glow_radiance(e, glow_radius_out);
    gl_Position = view_projection * vec4(e.position.xyz, 1.0);  // listed only where kept and in front
    gl_PointSize = ceil(2.0 * glow_radius_out + 1.0);
}
