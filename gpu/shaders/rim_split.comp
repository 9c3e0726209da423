#version 450 core
// Sort the scene's triangles for one paraboloid hemisphere by its rim plane (z = 0 in
// hemisphere space): wholly in front (projected per vertex, dpm.vert), crossing the rim
// (clipped first, dpm.geom), wholly behind (skipped). Each list is the index buffer of a
// DrawElementsIndirect command whose count the atomics fill. A first dispatch with
// `reset` writes both commands empty (on the GPU: a buffer upload would wait for the
// previous draws that read them).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };  // 9 floats a vertex
layout(std430, binding = 1) buffer Commands { uint commands[]; };  // front, then crossing: 5 uints each
layout(std430, binding = 2) writeonly buffer Front { uint front[]; };
layout(std430, binding = 3) writeonly buffer Crossing { uint crossing[]; };
uniform mat4 hemisphere_view;
uniform int triangle_count;
uniform bool reset;

void main() {
    if (reset) {
        if (gl_GlobalInvocationID.x < 10u) commands[gl_GlobalInvocationID.x] = gl_GlobalInvocationID.x % 5u == 1u ? 1u : 0u;
        return;
    }
    int triangle = int(gl_GlobalInvocationID.x);
    if (triangle >= triangle_count) return;
    int in_front = 0;
    for (int i = 0; i < 3; ++i) {
        int v = (triangle * 3 + i) * 9;
        vec3 p = vec3(vertices[v], vertices[v + 1], vertices[v + 2]);
        if ((hemisphere_view * vec4(p, 1.0)).z >= 0.0) in_front += 1;
    }
    if (in_front == 0) return;
    uint first = uint(triangle * 3);
    if (in_front == 3) {
        uint slot = atomicAdd(commands[0], 3u);
        front[slot] = first;
        front[slot + 1] = first + 1u;
        front[slot + 2] = first + 2u;
    } else {
        uint slot = atomicAdd(commands[5], 3u);
        crossing[slot] = first;
        crossing[slot + 1] = first + 1u;
        crossing[slot + 2] = first + 2u;
    }
}
