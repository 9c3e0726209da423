#version 450 core
// The emitters' first bounce (gpu/emitter_bounce.py): each receiver, a point on the
// surfaces (one workgroup of LANES), sums the irradiance the emitters of one set give
// it, through a march over the grid levels' occupancy, every `stride`-th emitter from
// its own offset, the sum scaled by `stride`. One dispatch adds the emitters [first,
// first + batch) into `irradiance`, each side of the surface's apart (a triangle's
// winding says nothing of where its room is), but not the side that looks into a solid
// (gpu/closed_meshes.py); with `finish`, the receiver becomes a VPL facing its brighter
// side, in that side's room: its flux its albedo times that side's irradiance times the
// area it stands for. A side gathers only the senders that light its room (rooms.glsl).
// An emissive surface's emitter nearer a
// receiver than GAP_VOXELS finest voxels lights it not: the occupancy cannot tell what
// lies between (a ceiling over a panel hung just under it would send the panel's back
// light past the panel, which holds it in); a point emitter's near light is kept.
#include "common.glsl"
#include "emitter.glsl"
#include "levels_march.glsl"
#include "rooms.glsl"
layout(local_size_x = LANES) in;
layout(std430, binding = 0) readonly buffer Senders { Emitter senders[]; };
// A receiver (receiver_draw.comp): position (w 1), face normal and the area it stands
// for, albedo, and its triangle's byte: the sides light reaches (bit 0: the side its normal
// faces, bit 1: the other) and the room each looks into (gpu/closed_meshes.py).
struct Receiver { vec4 position; vec4 normal; vec3 albedo; float code; };
layout(std430, binding = 1) readonly buffer Receivers { Receiver receivers[]; };
layout(std430, binding = 2) buffer Irradiance { vec4 irradiance[]; };  // front, back per receiver
layout(std430, binding = 3) writeonly buffer Lit { Emitter lit[]; };
uniform int receiver_count;
uniform int sender_count;
uniform int first_sender;
uniform int batch;
uniform int stride;
uniform int pattern;
uniform bool accumulate;
uniform bool finish;

shared vec3 sums[2][LANES];
const float GAP_VOXELS = 3.0;  // finest voxels within which an emissive surface lights no receiver

void main() {
    int index = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);
    if (index >= receiver_count) return;
    int lane = int(gl_LocalInvocationID.x);
    Receiver r = receivers[index];
    vec3 offset_along = EMITTER_OFFSET * level_voxels[0] * r.normal.xyz;
    uint code = uint(r.code);
    int rooms[2] = int[2](side_room(code, true), side_room(code, false));
    int offset = (index * 7919 + pattern) % stride;
    int last = min(first_sender + batch, sender_count);
    float gap = GAP_VOXELS * level_voxels[0];
    int start = first_sender + (offset - first_sender % stride + stride) % stride;
    vec3 sum[2] = vec3[2](vec3(0.0), vec3(0.0));
    for (int j = start + lane * stride; j < last; j += LANES * stride) {
        Emitter e = senders[j];
        if (e.position.w <= 0.0) continue;
        vec3 d = r.position.xyz - e.position.xyz;
        if (dot(d, d) < gap * gap && dot(e.normal.xyz, e.normal.xyz) > 0.5) continue;
        float facing = -dot(r.normal.xyz, d) * inversesqrt(max(dot(d, d), 1e-30));
        int side = facing > 0.0 ? 0 : 1;
        if ((code & (1u << side)) == 0u || !lights_room(e.position, rooms[side])) continue;
        // a receiver holds every sender's bound: it never shrinks here
        vec3 light = bounded_emitter_light(e, d, 0.0, singularity_bound, 1.0) * abs(facing);
        if (max(light.r, max(light.g, light.b)) <= 0.0) continue;
        vec3 from = e.position.xyz + EMITTER_OFFSET * level_voxels[0] * e.normal.xyz;
        if (levels_blocked(from, r.position.xyz + (side == 0 ? offset_along : -offset_along), e.position.xyz)) continue;
        sum[side] += light;
    }
    for (int side = 0; side < 2; ++side) sums[side][lane] = sum[side] * float(stride);
    barrier();
    for (int step = LANES / 2; step > 0; step /= 2) {
        if (lane < step)
            for (int side = 0; side < 2; ++side) sums[side][lane] += sums[side][lane + step];
        barrier();
    }
    if (lane != 0) return;
    vec3 front = sums[0][0] + (accumulate ? irradiance[2 * index].rgb : vec3(0.0));
    vec3 back = sums[1][0] + (accumulate ? irradiance[2 * index + 1].rgb : vec3(0.0));
    irradiance[2 * index] = vec4(front, 0.0);
    irradiance[2 * index + 1] = vec4(back, 0.0);
    if (!finish) return;
    bool back_brighter = dot(back, vec3(1.0)) > dot(front, vec3(1.0));
    Emitter vpl;
    vpl.position = vec4(r.position.xyz, room_word(rooms[back_brighter ? 1 : 0]));
    vpl.normal = vec4(back_brighter ? -r.normal.xyz : r.normal.xyz, r.normal.w);
    vpl.flux = vec4(r.albedo * (back_brighter ? back : front) * r.normal.w, 1.0);  // its bound held
    lit[index] = vpl;
}
