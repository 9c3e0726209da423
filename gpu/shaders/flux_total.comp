#version 450 core
// Sums the flux of one set of emitter rows (emitter.glsl) into totals[slot], one
// workgroup striding over the set (gpu/bounces.py conserve): what a generation and its
// senders carry, kept on the GPU so a frame does not wait to read it.
#include "common.glsl"
#include "emitter.glsl"
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Rows { Emitter rows[]; };
layout(std430, binding = 1) buffer Totals { vec4 totals[]; };
uniform int row_count;
uniform int slot;
uniform bool accumulate;  // add to the slot (another sender set) rather than start it

shared vec3 sums[256];

void main() {
    uint lane = gl_LocalInvocationID.x;
    vec3 sum = vec3(0.0);
    for (int i = int(lane); i < row_count; i += 256)
        if (rows[i].position.w > 0.0) sum += rows[i].flux.rgb;
    sums[lane] = sum;
    barrier();
    for (uint step = 128u; step > 0u; step >>= 1u) {
        if (lane < step) sums[lane] += sums[lane + step];
        barrier();
    }
    if (lane == 0u) totals[slot] = vec4(sums[0] + (accumulate ? totals[slot].rgb : vec3(0.0)), 0.0);
}
