#version 450 core
// One more bounce of a light's VPLs (gpu/bounces.py): each VPL (a receiver, one
// workgroup of LANES) sums the irradiance the last generation of the same light's VPLs
// gives it, through a march over the grid levels' occupancy; its lanes share the senders. A receiver
// takes every `stride`-th sender from its own offset, the sum scaled by `stride`, so the
// cost stays a few hundred marches a receiver and the subsets change with the receiver
// (and the VPL pattern, when frames converge). One dispatch adds the senders [first,
// first + batch) of one set into `irradiance`; with `finish`, the receiver's next
// generation is written, its flux the first generation's times indirect over direct
// irradiance (flux = albedo x direct irradiance x area, the cell's sums), at most its
// area times the indirect irradiance (albedo <= 1: where the direct light at the VPL's
// texel is far below its cell's, at a spot's edge, the ratio would run away), and added
// to the total that the indirect stage gathers.
#include "common.glsl"
#include "emitter.glsl"
#include "light.glsl"
#include "levels_march.glsl"
layout(local_size_x = LANES) in;
layout(std430, binding = 0) readonly buffer Senders { Emitter senders[]; };
layout(std430, binding = 1) readonly buffer Receivers { Emitter receivers[]; };  // the first generation
layout(std430, binding = 2) buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = 3) writeonly buffer Next { Emitter next[]; };
layout(std430, binding = 4) buffer Total { Emitter total[]; };
uniform int receiver_count;
uniform int sender_count;
uniform int first_sender;
uniform int batch;
uniform int stride;
uniform int pattern;
uniform bool accumulate;
uniform bool finish;

shared vec3 sums[LANES];

vec3 direct_irradiance(vec3 p, vec3 n) {
    vec3 w;
    float dist;
    light_ray(p, w, dist);
    return light_irradiance(w, dist, max(0.0, -dot(n, w)));
}

void main() {
    int index = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);
    if (index >= receiver_count) return;
    int lane = int(gl_LocalInvocationID.x);
    Emitter r = receivers[index];
    vec3 sum = vec3(0.0);
    if (r.position.w > 0.0) {
        vec3 to = r.position.xyz + EMITTER_OFFSET * level_voxels[0] * r.normal.xyz;
        int offset = (index * 7919 + pattern) % stride;
        int last = min(first_sender + batch, sender_count);
        int start = first_sender + (offset - first_sender % stride + stride) % stride;
        for (int j = start + lane * stride; j < last; j += LANES * stride) {
            Emitter e = senders[j];
            if (e.position.w <= 0.0) continue;
            vec3 d = r.position.xyz - e.position.xyz;
            float facing = -dot(r.normal.xyz, d) * inversesqrt(max(dot(d, d), 1e-30));
            if (facing <= 0.0) continue;
            vec3 light = emitter_light(e, d) * facing;
            if (max(light.r, max(light.g, light.b)) <= 0.0) continue;
            if (levels_blocked(e.position.xyz + EMITTER_OFFSET * level_voxels[0] * e.normal.xyz, to, e.position.xyz))
                continue;
            sum += light;
        }
    }
    sums[lane] = sum * float(stride);
    barrier();
    for (int step = LANES / 2; step > 0; step /= 2) {
        if (lane < step) sums[lane] += sums[lane + step];
        barrier();
    }
    if (lane != 0) return;
    vec3 received = sums[0] + (accumulate ? irradiance[index].rgb : vec3(0.0));
    irradiance[index] = vec4(received, 0.0);
    if (!finish) return;
    Emitter generation = r;
    vec3 direct = r.position.w > 0.0 ? direct_irradiance(r.position.xyz, r.normal.xyz) : vec3(0.0);
    generation.flux = vec4(0.0);
    for (int c = 0; c < 3; ++c)
        if (direct[c] > 0.0) generation.flux[c] = min(r.flux[c] * received[c] / direct[c], r.normal.w * received[c]);
    next[index] = generation;
    total[index].flux += generation.flux;
}
