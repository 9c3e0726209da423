// The surface at a fragment of a raster pass, read from the vertex buffer (bound at 5,
// gpu/mesh_buffer.py) by the triangle's number and the fragment's barycentric weights:
// the rasterizer interpolates two floats, not every attribute, which on a GPU with few
// raster units costs more than the whole fragment (docs/performance.md, "Raster passes").
#include "vertex_layout.glsl"
layout(std430, binding = 5) readonly buffer SurfaceVertices { float surface_vertices[]; };
flat in int surface_triangle;
in vec2 surface_weights;  // the weights of the triangle's second and third corners

float surface_float(int offset) {
    int at = 3 * VERTEX_FLOATS * surface_triangle + offset;
    return (1.0 - surface_weights.x - surface_weights.y) * surface_vertices[at]
        + surface_weights.x * surface_vertices[at + VERTEX_FLOATS]
        + surface_weights.y * surface_vertices[at + 2 * VERTEX_FLOATS];
}

vec3 surface_vec3(int offset) {
    return vec3(surface_float(offset), surface_float(offset + 1), surface_float(offset + 2));
}

vec4 surface_vec4(int offset) {
    return vec4(surface_vec3(offset), surface_float(offset + 3));
}
