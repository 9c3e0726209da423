#version 450 core
// Each filled cluster of emitter_cluster.comp becomes one emitter at the flux-weighted mean
// of its emitters' places, with their mean normal, summed flux and share of it whose bound
// is held, and its name and octave in position.w (cluster_key.glsl). A cluster with a
// normal stands for the area its emitters stand for, at most its cell's face (a square:
// emitter.glsl square_faces); one without, for a disk as wide as the finest clusters'
// cell. A glossy cluster's lobe lies along its emitters' mean axis, as wide as theirs and
// their axes' spread together: to its emitters' mean alpha squared (a lobe's spread of
// angles squared, over 2) adds half of one minus their mean axis' length (the axes' mean
// angle squared, over 4) (docs/method.md, "Glossy VPLs"). The list keeps the hash table's slot order, so a frame's sums come out the same
// every time: STAGE 0 counts each block of 64 slots,
// STAGE 1 (one invocation) turns the counts into offsets after the octaves listed before
// and the total into `emitter_total`, STAGE 2 writes each cluster at its block's offset
// plus its rank in the block.
#include "common.glsl"
#include "emitter.glsl"
#include "cluster_key.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 1) readonly buffer Keys { int keys[]; };  // key + 1, 0: empty
layout(std430, binding = 2) readonly buffer Sums { int sums[]; };
layout(std430, binding = 3) buffer Count { int emitter_total; int octave_start[]; };
layout(std430, binding = 4) buffer Blocks { int blocks[]; };  // per 64 slots: count, then offset
uniform int capacity;
uniform vec3 level_origins[LEVELS];
uniform float level_cells[LEVELS];
uniform int grid_size;
uniform int octave;
uniform float flux_scale;

shared int filled[64];

bool is_filled(int slot) {
    if (slot >= capacity || keys[slot] == 0) return false;
    int base = slot * CLUSTER_INTS;
    return sums[base + 9] > 0 && max(sums[base], max(sums[base + 1], sums[base + 2])) > 0;
}

void main() {
    int slot = int(gl_GlobalInvocationID.x);
    int lane = int(gl_LocalInvocationID.x);
    int block = int(gl_WorkGroupID.x);
#if STAGE == 1
    if (slot != 0) return;
    int total = emitter_total;
    octave_start[octave] = total;
    for (int b = 0; b < (capacity + 63) / 64; ++b) {
        int count = blocks[b];
        blocks[b] = total;
        total += count;
    }
    emitter_total = total;
#else
    filled[lane] = is_filled(slot) ? 1 : 0;
    barrier();
#if STAGE == 0
    if (lane == 0) {
        int count = 0;
        for (int i = 0; i < 64; ++i) count += filled[i];
        blocks[block] = count;
    }
#else
    if (filled[lane] == 0) return;
    int rank = 0;
    for (int i = 0; i < lane; ++i) rank += filled[i];
    int base = slot * CLUSTER_INTS;
    float weight = float(sums[base + 9]);
    vec3 flux = vec3(sums[base], sums[base + 1], sums[base + 2]) / flux_scale;
    int key = keys[slot] - 1;
    int level, bin, room;
    ivec3 cell;
    cluster_cell(key, grid_size, LEVELS, level, cell, bin, room);
    float size = level_cells[level] * float(1 << octave);
    vec3 place = vec3(sums[base + 3], sums[base + 4], sums[base + 5]) / weight;
    vec3 n = vec3(sums[base + 6], sums[base + 7], sums[base + 8]) / weight;
    vec3 normal = bin != NO_NORMAL_BIN && dot(n, n) > 1e-12 ? normalize(n) : vec3(0.0);
    float cell_area = level_cells[level] * level_cells[level];
    float area = dot(normal, normal) > 0.5 ? min(float(uint(sums[base + 11])) / float(AREA_UNITS) * cell_area, size * size)
                                           : PI * 0.25 * cell_area;
    float share = float(sums[base + 10]) / weight;
    if (bin >= GLOSSY_BINS) share = -min(sqrt(share + 0.5 * max(1.0 - length(n), 0.0)), 1.0);  // -(its alpha)
    emitters[blocks[block] + rank] = Emitter(vec4(level_origins[level] + (vec3(cell) + clamp(place, 0.0, 1.0)) * size,
                                                  cluster_word(key, octave)),
                                             vec4(normal, area),
                                             vec4(flux, share));
#endif
#endif
}
