#version 450 core
// The cells of one light grid that a lookup can read (gpu/light_grid.py): those whose
// centres lie within LOOKUP_REACH cells of a triangle, any triangle, seen or casting
// shadows or not (light_grid_lookup.glsl reads the eight centres around p + n cell/2, so
// at most 1.5 cells from the surface point p). The gather skips the others. The cells
// near the triangle's plane are walked along the normal's largest axis, the other two
// over the triangle's box: a large triangle costs its area in cells, within llvmpipe's
// loop limit.
#include "vertex_layout.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };  // vertex_layout.glsl
#include "vertex_position.glsl"
layout(r8ui, binding = 0) uniform writeonly uimage3D receiving;
uniform vec3 grid_origin;
uniform float cell_size;
uniform int grid_size;
uniform int layer;  // this grid's block along z
uniform int triangle_count;
uniform int first_triangle;  // this dispatch's first (context.py dispatch_row)
const float LOOKUP_REACH = 1.5;

vec3 corner_cells(int triangle, int k) {
    return (vertex_position(triangle * 3 + k) - grid_origin) / cell_size - 0.5;  // centres at integers
}

void main() {
    int triangle = first_triangle + int(gl_GlobalInvocationID.x);
    if (triangle >= triangle_count) return;
    vec3 a = corner_cells(triangle, 0), b = corner_cells(triangle, 1), c = corner_cells(triangle, 2);
    ivec3 first = max(ivec3(ceil(min(a, min(b, c)) - LOOKUP_REACH)), ivec3(0));
    ivec3 last = min(ivec3(floor(max(a, max(b, c)) + LOOKUP_REACH)), ivec3(grid_size - 1));
    if (any(greaterThan(first, last))) return;
    vec3 n = cross(b - a, c - a);
    float area = length(n);
    n = area > 0.0 ? n / area : vec3(0.0);
    // |n . (centre - a)| <= slab holds for every centre within LOOKUP_REACH (per axis) of the plane
    float slab = LOOKUP_REACH * (abs(n.x) + abs(n.y) + abs(n.z));
    vec3 m = abs(n);
    int w = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);  // walked along the normal's largest axis
    int u = (w + 1) % 3, v = (w + 2) % 3;
    for (int i = first[u]; i <= last[u]; ++i) {
        for (int j = first[v]; j <= last[v]; ++j) {
            int from = first[w], to = last[w];
            if (area > 0.0) {  // the centres along w within the slab: n . (centre - a) in [-slab, slab]
                float rest = n[u] * (float(i) - a[u]) + n[v] * (float(j) - a[v]);
                float low = (-slab - rest) / n[w] + a[w], high = (slab - rest) / n[w] + a[w];
                from = max(from, int(ceil(min(low, high))));
                to = min(to, int(floor(max(low, high))));
            }
            for (int k = from; k <= to; ++k) {
                ivec3 cell;
                cell[u] = i; cell[v] = j; cell[w] = k;
                imageStore(receiving, cell + ivec3(0, 0, layer * grid_size), uvec4(1u));
            }
        }
    }
}
