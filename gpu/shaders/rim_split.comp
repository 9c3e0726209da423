#version 450 core
// Sort the scene's triangles for one paraboloid hemisphere by its rim plane (z = 0 in
// hemisphere space): wholly in front (projected per vertex, dpm.vert), crossing the rim
// (clipped first, dpm.geom), wholly behind (skipped). One index buffer holds both lists,
// the front one from 0 and the crossing one from `capacity`; each is drawn by a
// DrawElementsIndirect command whose count the atomics fill. A first dispatch with
// `reset` writes both commands empty (on the GPU: a buffer upload would wait for the
// previous draws that read them).
#include "vertex_layout.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };  // vertex_layout.glsl
#include "vertex_position.glsl"
layout(std430, binding = 1) buffer Commands { uint commands[]; };  // front, then crossing: 5 uints each
layout(std430, binding = 2) writeonly buffer Lists { uint lists[]; };
uniform mat4 hemisphere_view;
uniform int first_triangle;  // the lights' triangles: first_triangle .. + triangle_count
uniform int triangle_count;
uniform uint capacity;  // indices per list: 3 per triangle
uniform bool reset;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (reset) {
        // (count, instances, first index, base vertex, base instance) of both commands.
        if (i < 10u) commands[i] = i % 5u == 1u ? 1u : (i == 7u ? capacity : 0u);
        return;
    }
    if (int(i) >= triangle_count) return;
    int triangle = first_triangle + int(i);
    int in_front = 0;
    for (int k = 0; k < 3; ++k) {
        if ((hemisphere_view * vec4(vertex_position(triangle * 3 + k), 1.0)).z >= 0.0) in_front += 1;
    }
    if (in_front == 0) return;
    bool front = in_front == 3;
    uint slot = atomicAdd(commands[front ? 0 : 5], 3u) + (front ? 0u : capacity);
    uint first = uint(triangle * 3);
    for (uint k = 0u; k < 3u; ++k) lists[slot + k] = first + k;
}
