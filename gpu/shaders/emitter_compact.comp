#version 450 core
// Each filled cluster of emitter_cluster.comp becomes one emitter at the flux-weighted mean
// of its emitters' places, with their mean normal and summed flux, standing for a disk
// as wide as its cell; the count goes to `emitter_count`.
#include "common.glsl"
#include "emitter.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 1) readonly buffer Keys { int keys[]; };
layout(std430, binding = 2) readonly buffer Sums { int sums[]; };
layout(std430, binding = 3) buffer Count { int emitter_count; };
uniform int capacity;
uniform vec3 level_origins[LEVELS];
uniform float level_cells[LEVELS];
uniform int grid_size;
uniform float flux_scale;

void main() {
    int slot = int(gl_GlobalInvocationID.x);
    if (slot >= capacity || keys[slot] < 0) return;
    int base = slot * CLUSTER_INTS;
    float weight = float(sums[base + 9]);
    vec3 flux = vec3(sums[base], sums[base + 1], sums[base + 2]) / flux_scale;
    if (weight <= 0.0 || max(flux.r, max(flux.g, flux.b)) <= 0.0) return;
    int key = keys[slot];
    int bin = key % 7;
    int cell_index = key / 7;
    ivec3 cell = ivec3(cell_index % grid_size, (cell_index / grid_size) % grid_size,
                       (cell_index / (grid_size * grid_size)) % grid_size);
    int level = cell_index / (grid_size * grid_size * grid_size);
    float size = level_cells[level];
    vec3 place = vec3(sums[base + 3], sums[base + 4], sums[base + 5]) / weight;
    vec3 n = vec3(sums[base + 6], sums[base + 7], sums[base + 8]) / weight;
    vec3 normal = bin < 6 && dot(n, n) > 1e-12 ? normalize(n) : vec3(0.0);
    int out_index = atomicAdd(emitter_count, 1);
    emitters[out_index] = Emitter(vec4(level_origins[level] + (vec3(cell) + clamp(place, 0.0, 1.0)) * size, 1.0),
                                  vec4(normal, PI * 0.25 * size * size), vec4(flux, 0.0));
}
