#version 450 core
// Voxelisation of the small triangles (gpu/light_grid.py): each is sampled at points less
// than half a voxel apart, in every grid, marking the voxels (and their cells) it passes.
// A triangle that would take more than MOST_STEPS samples along an edge in the finest grid
// has its edges walked here and goes to a list drawn by occupancy.frag (a DrawElementsIndirect command whose
// count the atomics fill; a first dispatch with `reset` writes it empty). Grids lie one
// after the other along z in one occupancy volume and one coarse volume.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };  // 12 floats a vertex (mesh_buffer.py)
layout(std430, binding = 1) buffer Command { uint command[]; };  // count, instances, first index, base vertex, base instance
layout(std430, binding = 2) writeonly buffer Large { uint large[]; };
layout(r8ui, binding = 0) uniform writeonly uimage3D occupancy;
layout(r8ui, binding = 1) uniform writeonly uimage3D coarse;
uniform vec3 grid_origins[GRIDS];
uniform float voxel_sizes[GRIDS];
uniform int voxels;           // a grid's voxels along each side
uniform int voxels_per_cell;
uniform int first_triangle;   // the lights' triangles: first_triangle .. + triangle_count
uniform int triangle_count;
uniform bool reset;
const int MOST_STEPS = 16;

vec3 corner(int triangle, int k) {
    int v = (triangle * 3 + k) * 12;
    return vec3(vertices[v], vertices[v + 1], vertices[v + 2]);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (reset) {
        if (i < 5u) command[i] = i == 1u ? 1u : 0u;
        return;
    }
    if (int(i) >= triangle_count) return;
    int triangle = first_triangle + int(i);
    vec3 a = corner(triangle, 0), b = corner(triangle, 1), c = corner(triangle, 2);
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
                vec3 d = end - start, inverse = 1.0 / (d + vec3(1e-30));
                vec3 t0 = -start * inverse, t1 = (vec3(voxels) - start) * inverse;
                float enter = max(0.0, max(max(min(t0.x, t1.x), min(t0.y, t1.y)), min(t0.z, t1.z)));
                float leave = min(1.0, min(min(max(t0.x, t1.x), max(t0.y, t1.y)), max(t0.z, t1.z)));
                if (enter > leave) continue;
                int steps = min(int(ceil(length(d) * (leave - enter) * 2.0)), 4 * voxels);
                for (int i = 0; i <= steps; ++i) {
                    ivec3 v = ivec3(floor(start + d * mix(enter, leave, float(i) / float(max(steps, 1)))));
                    if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, ivec3(voxels)))) continue;
                    imageStore(occupancy, v + ivec3(0, 0, g * voxels), uvec4(1u));
                    imageStore(coarse, v / voxels_per_cell + ivec3(0, 0, g * (voxels / voxels_per_cell)), uvec4(1u));
                }
            }
        }
        return;
    }
    for (int g = 0; g < GRIDS; ++g) {
        int steps = max(1, int(ceil(longest / (0.5 * voxel_sizes[g]))));
        for (int s = 0; s <= steps; ++s) {
            for (int t = 0; t <= steps - s; ++t) {
                vec3 p = a + (b - a) * (float(s) / float(steps)) + (c - a) * (float(t) / float(steps));
                ivec3 v = ivec3(floor((p - grid_origins[g]) / voxel_sizes[g]));
                if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, ivec3(voxels)))) continue;
                imageStore(occupancy, v + ivec3(0, 0, g * voxels), uvec4(1u));
                imageStore(coarse, v / voxels_per_cell + ivec3(0, 0, g * (voxels / voxels_per_cell)), uvec4(1u));
            }
        }
    }
}
