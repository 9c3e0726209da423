#version 450 core
// The room of each cell of one light grid that a lookup can read (gpu/light_grid.py): its
// `receiving` mark (light_grid_receiving.comp) becomes 1 + the innermost room (rooms.glsl)
// holding its centre, by the parity of a ray's crossings of the room's walls, as
// gpu/closed_meshes.py sorts the faces; 1 outside every room. The gather then sums only
// that room's clusters: the light of a lamp shut in a closed mesh reaches no cell outside
// it, whatever wall a march from the cell misses.
#include "vertex_layout.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };  // vertex_layout.glsl
#include "vertex_position.glsl"
layout(std430, binding = 1) readonly buffer Walls { int walls[]; };  // the rooms' triangles' numbers, room 1's first
layout(r8ui, binding = 0) uniform uimage3D receiving;
uniform vec3 grid_origin;
uniform float cell_size;
uniform int grid_size;
uniform int layer;  // this grid's block along z
uniform int room_count;
uniform int first_wall[ROOM_CODES];
uniform int wall_count[ROOM_CODES];
uniform vec3 room_low[ROOM_CODES];
uniform vec3 room_high[ROOM_CODES];
uniform vec3 ray;  // off every axis and diagonal (gpu/closed_meshes.py RAY)

// Whether the ray from p crosses triangle `triangle` (Moller and Trumbore 1997).
bool crosses(vec3 p, int triangle) {
    vec3 a = vertex_position(3 * triangle), b = vertex_position(3 * triangle + 1), c = vertex_position(3 * triangle + 2);
    vec3 edge1 = b - a, edge2 = c - a;
    vec3 q = cross(ray, edge2);
    float det = dot(edge1, q);
    if (abs(det) <= 1e-30) return false;
    float inverse = 1.0 / det;
    vec3 s = p - a;
    float u = dot(s, q) * inverse;
    vec3 r = cross(s, edge1);
    float v = dot(ray, r) * inverse;
    return u >= 0.0 && v >= 0.0 && u + v <= 1.0 && dot(edge2, r) * inverse > 0.0;
}

void main() {
    int index = int(gl_GlobalInvocationID.x);
    if (index >= grid_size * grid_size * grid_size) return;
    ivec3 cell = ivec3(index % grid_size, (index / grid_size) % grid_size, index / (grid_size * grid_size));
    ivec3 at = cell + ivec3(0, 0, layer * grid_size);
    if (imageLoad(receiving, at).r == 0u) return;
    vec3 centre = grid_origin + (vec3(cell) + 0.5) * cell_size;
    int room = 0;
    for (int k = 0; k < room_count && room == 0; ++k) {
        if (any(lessThan(centre, room_low[k])) || any(greaterThan(centre, room_high[k]))) continue;
        int crossings = 0;
        for (int t = first_wall[k]; t < first_wall[k] + wall_count[k]; ++t) crossings += crosses(centre, walls[t]) ? 1 : 0;
        if ((crossings & 1) == 1) room = k + 1;
    }
    imageStore(receiving, at, uvec4(uint(1 + room)));
}
