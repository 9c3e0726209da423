// The scene's vertex buffer (gpu/mesh_buffer.py SURFACE_VERTICES_BINDING) as the raster
// passes' fragments and the G-buffer's resolve read it: a triangle's corners mixed by
// barycentric weights (those of its second and third corners).
#include "vertex_layout.glsl"
layout(std430, binding = 5) readonly buffer SurfaceVertices { float vertices[]; };
#include "vertex_position.glsl"

float corner_mix(int triangle, vec2 w, int offset) {
    int at = 3 * VERTEX_FLOATS * triangle + offset;
    return (1.0 - w.x - w.y) * vertices[at] + w.x * vertices[at + VERTEX_FLOATS] + w.y * vertices[at + 2 * VERTEX_FLOATS];
}

vec3 corner_mix3(int triangle, vec2 w, int offset) {
    return vec3(corner_mix(triangle, w, offset), corner_mix(triangle, w, offset + 1), corner_mix(triangle, w, offset + 2));
}

vec4 corner_mix4(int triangle, vec2 w, int offset) {
    return vec4(corner_mix3(triangle, w, offset), corner_mix(triangle, w, offset + 3));
}
