#version 450 core
// Voxelisation of the small triangles (gpu/light_grid.py): each is sampled at points less
// than half a voxel apart, in every grid, marking the voxels (and their cells) it passes.
// A triangle that would take more than MOST_STEPS samples along an edge in the finest grid
// has its edges walked here and goes to a list drawn by occupancy.frag (a
// DrawElementsIndirect command whose count the atomics fill; a first dispatch with `reset`
// writes it empty).
#include "occupancy_mark.glsl"
#include "segment.glsl"
#include "vertex_layout.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };  // vertex_layout.glsl
#include "vertex_position.glsl"
layout(std430, binding = 1) buffer Command { uint command[]; };  // count, instances, first index, base vertex, base instance
layout(std430, binding = 2) writeonly buffer Large { uint large[]; };
uniform vec3 grid_origins[GRIDS];
uniform float voxel_sizes[GRIDS];
uniform int first_triangle;   // the lights' triangles: first_triangle .. + triangle_count
uniform int triangle_count;
uniform bool reset;
uniform uint first_invocation;  // where this dispatch starts (gpu/context.py dispatch_row)
const int MOST_STEPS = 16;


void main() {
    uint i = first_invocation + gl_GlobalInvocationID.x;
    if (reset) {
        if (i < 5u) command[i] = i == 1u ? 1u : 0u;
        return;
    }
    if (int(i) >= triangle_count) return;
    int triangle = first_triangle + int(i);
    // A surface less than half opaque (glass, a faint card) lets the light through; one cut
    // out by an image's alpha occupies its voxels whole (docs/method.md).
    int first = triangle * 3 * VERTEX_FLOATS;
    if (vertices[first + VERTEX_ALPHA_LAYER] < -0.5 &&
        vertices[first + VERTEX_ALPHA] * (1.0 - vertices[first + VERTEX_TRANSMISSION]) < 0.5) return;
    vec3 a = vertex_position(triangle * 3), b = vertex_position(triangle * 3 + 1), c = vertex_position(triangle * 3 + 2);
    float longest = max(distance(a, b), max(distance(b, c), distance(c, a)));
    float finest = voxel_sizes[0];
    for (int g = 1; g < GRIDS; ++g) finest = min(finest, voxel_sizes[g]);
    if (longest > 0.5 * finest * float(MOST_STEPS)) {
        uint slot = atomicAdd(command[0], 3u);
        for (uint k = 0u; k < 3u; ++k) large[slot + k] = uint(triangle * 3) + k;
        // Rasterising marks only voxels whose centres the triangle covers: its edges are
        // walked here so that no gap opens along them (light would leak through).
        for (int g = 0; g < GRIDS; ++g) {
            for (int edge = 0; edge < 3; ++edge) {
                vec3 from = edge == 0 ? a : (edge == 1 ? b : c), to = edge == 0 ? b : (edge == 1 ? c : a);
                vec3 start = (from - grid_origins[g]) / voxel_sizes[g], end = (to - grid_origins[g]) / voxel_sizes[g];
                // The part of the edge inside the grid, in steps of half a voxel.
                vec2 inside = part_inside(start, end, float(voxels));
                if (inside.x > inside.y) continue;
                int steps = min(int(ceil(distance(start, end) * (inside.y - inside.x) * 2.0)), 4 * voxels);
                for (int i = 0; i <= steps; ++i)
                    mark_voxel(g, ivec3(floor(mix(start, end, mix(inside.x, inside.y, float(i) / float(max(steps, 1)))))));
            }
        }
        return;
    }
    for (int g = 0; g < GRIDS; ++g) {
        int steps = max(1, int(ceil(longest / (0.5 * voxel_sizes[g]))));
        for (int s = 0; s <= steps; ++s) {
            for (int t = 0; t <= steps - s; ++t) {
                vec3 p = a + (b - a) * (float(s) / float(steps)) + (c - a) * (float(t) / float(steps));
                mark_voxel(g, ivec3(floor((p - grid_origins[g]) / voxel_sizes[g])));
            }
        }
    }
}
