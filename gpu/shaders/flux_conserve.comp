#version 450 core
// Scales a generation's flux down, channel by channel, to at most its senders' total
// times `largest_albedo` (gpu/bounces.py conserve): totals[0] is the senders', totals[1]
// the generation's (flux_total.comp).
#include "common.glsl"
#include "emitter.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Rows { Emitter rows[]; };
layout(std430, binding = 1) readonly buffer Totals { vec4 totals[]; };
uniform int row_count;
uniform vec3 largest_albedo;

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= row_count) return;
    vec3 limit = totals[0].rgb * largest_albedo, carried = totals[1].rgb;
    vec3 scale = mix(vec3(1.0), limit / max(carried, vec3(1e-30)), greaterThan(carried, limit));
    rows[i].flux.rgb *= scale;
}
