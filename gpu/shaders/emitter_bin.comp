#version 450 core
// The emitter grid's finest clusters (gpu/emitter_grid.py): every point emitter adds its
// flux, its flux-weighted position and its flux-weighted area to the cell of the finest level that
// holds it (an emitter outside the grid to the nearest border cell: its own position
// still places its light).
#extension GL_NV_shader_atomic_float : require
#include "common.glsl"
#include "emitter.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 1) buffer Clusters { float clusters[]; };  // CLUSTER_FLOATS per cell
uniform int emitter_count;
uniform int first_emitter;  // this dispatch's first (a dispatch reaches 65,535 workgroups)
uniform vec3 grid_origin;
uniform float cell_size;
uniform int grid_size;

void main() {
    int index = first_emitter + int(gl_GlobalInvocationID.x);
    if (index >= emitter_count) return;
    Emitter e = emitters[index];
    float weight = e.flux.r + e.flux.g + e.flux.b;
    if (e.position.w <= 0.0 || !(weight > 0.0)) return;
    ivec3 cell = ivec3(clamp(floor((e.position.xyz - grid_origin) / cell_size), vec3(0.0), vec3(grid_size - 1)));
    int at = CLUSTER_FLOATS * (cell.x + grid_size * (cell.y + grid_size * cell.z));
    for (int c = 0; c < 3; ++c) atomicAdd(clusters[at + c], e.flux[c]);
    atomicAdd(clusters[at + 3], weight);
    for (int c = 0; c < 3; ++c) atomicAdd(clusters[at + 4 + c], weight * e.position[c]);
    atomicAdd(clusters[at + 7], weight * e.normal.w);
}
