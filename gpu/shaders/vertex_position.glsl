// A vertex's position, read as floats from the scene's vertex buffer (vertex_layout.glsl)
// by a compute pass: included after the pass declares its `vertices` buffer.
vec3 vertex_position(int vertex) {
    int v = vertex * VERTEX_FLOATS;
    return vec3(vertices[v], vertices[v + 1], vertices[v + 2]);
}
