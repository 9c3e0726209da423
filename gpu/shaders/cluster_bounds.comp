#version 450 core
// The box of each cluster of CLUSTER_TRIANGLES consecutive triangles of a range
// (gpu/mesh_buffer.py): what frustum_cull.comp tests a view against.
#include "vertex_layout.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 6) readonly buffer Vertices { float vertices[]; };  // vertex_layout.glsl
#include "vertex_position.glsl"
layout(std430, binding = 7) writeonly buffer Boxes { vec4 boxes[]; };  // low, high per cluster
uniform int first_triangle;
uniform int triangle_count;

void main() {
    int cluster = int(gl_GlobalInvocationID.x);
    int start = cluster * CLUSTER_TRIANGLES;
    if (start >= triangle_count) return;
    int end = min(start + CLUSTER_TRIANGLES, triangle_count);
    vec3 low = vec3(3.4e38), high = vec3(-3.4e38);
    for (int v = (first_triangle + start) * 3; v < (first_triangle + end) * 3; ++v) {
        low = min(low, vertex_position(v));
        high = max(high, vertex_position(v));
    }
    boxes[2 * cluster] = vec4(low, 0.0);
    boxes[2 * cluster + 1] = vec4(high, 0.0);
}
