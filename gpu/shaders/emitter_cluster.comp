#version 450 core
// Emitters into clusters: the finest level whose box holds an emitter decides its cluster
// cell, its lobe's main axis and sign (a cosine normal's or a glossy lobe's, or "no
// normal": cluster_key.glsl) the bin and with ROOMS its room (rooms.glsl) the room; a hash
// table finds the cluster, which sums the flux and the flux-weighted place in its cell,
// normal (or lobe axis) and share whose bound is held (emitter.glsl held_share; a glossy
// lobe's: its alpha squared), and the area its emitters stand for, in fixed-point
// integer atomics (the same sums whatever order the emitters come in).
// With WIDER, the emitters are the clusters of the octave before (emitter_compact.comp's list) and each goes into the cell twice as
// wide that holds its own, by its name (cluster_key.glsl), not its place.
#include "common.glsl"
#include "emitter.glsl"
#include "cluster_key.glsl"
#include "rooms.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 1) buffer Keys { int keys[]; };     // key + 1, 0: empty
layout(std430, binding = 2) buffer Sums { int sums[]; };     // CLUSTER_INTS per slot
layout(std430, binding = 3) readonly buffer Count { int emitter_total; int octave_start[]; };
uniform int emitter_count;
uniform int capacity;                  // a power of two
uniform vec3 level_origins[LEVELS];
uniform float level_cells[LEVELS];
uniform int grid_size;
uniform int octave;                    // the clusters' width: level_cells << octave
uniform float flux_scale;              // fixed-point units per W
uniform int first_emitter;             // this dispatch's first (gpu/context.py dispatch_row)

void main() {
    int index = first_emitter + int(gl_GlobalInvocationID.x);
#if WIDER
    int first = octave_start[octave - 1];
    if (index >= emitter_total - first) return;
    Emitter e = emitters[first + index];
    int level, bin, room;
    ivec3 cell;
    cluster_cell(cluster_word_key(e.position.w), grid_size, LEVELS, level, cell, bin, room);
    cell >>= 1;
    vec3 g = (e.position.xyz - level_origins[level]) / (level_cells[level] * float(1 << octave));
    vec3 n = e.normal.xyz;
#else
    if (index >= emitter_count || emitters[index].position.w <= 0.0) return;
    Emitter e = emitters[index];
    int level = LEVELS - 1;
    for (int l = LEVELS - 1; l >= 0; --l) {
        vec3 g = (e.position.xyz - level_origins[l]) / level_cells[l];
        if (all(greaterThanEqual(g, vec3(0.0))) && all(lessThan(g, vec3(grid_size)))) level = l;
    }
    vec3 g = clamp((e.position.xyz - level_origins[level]) / level_cells[level], vec3(0.0), vec3(grid_size) - 1e-3);
    ivec3 cell = ivec3(floor(g));
    vec3 n = e.normal.xyz;
    int bin = dot(n, n) > 0.5 ? axis_bin(n, glossy_lobe(e)) : NO_NORMAL_BIN;
#ifdef ROOMS
    int room = emitter_room(e.position);
#else
    int room = 0;
#endif
#endif
    int key = cluster_key(level, cell, bin, room, grid_size, LEVELS);
    int slot = int(uint(key) * 2654435761u) & (capacity - 1);
    for (int probe = 0; probe < capacity; ++probe) {
        int held = atomicCompSwap(keys[slot], 0, key + 1);
        if (held == 0 || held == key + 1) break;
        slot = (slot + 1) & (capacity - 1);
    }
    vec3 flux = e.flux.rgb * flux_scale;
    float weight = (flux.r + flux.g + flux.b) / 3.0;
    int base = slot * CLUSTER_INTS;
    atomicAdd(sums[base + 0], int(round(flux.r)));
    atomicAdd(sums[base + 1], int(round(flux.g)));
    atomicAdd(sums[base + 2], int(round(flux.b)));
    vec3 place = clamp(g - vec3(cell), 0.0, 1.0) * weight;
    vec3 turned = n * weight;
    for (int k = 0; k < 3; ++k) {
        atomicAdd(sums[base + 3 + k], int(round(place[k])));
        atomicAdd(sums[base + 6 + k], int(round(turned[k])));
    }
    atomicAdd(sums[base + 9], int(round(weight)));
    atomicAdd(sums[base + 10], int(round(weight * (glossy_lobe(e) ? e.flux.w * e.flux.w : held_share(e)))));
    float cell_area = level_cells[level] * level_cells[level];
    atomicAdd(sums[base + 11], int(round(min(e.normal.w / cell_area, float(MEMBER_AREA_CAP)) * float(AREA_UNITS))));
}
