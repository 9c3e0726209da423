#version 450 core
// World-space vertices for the stages that clip or subdivide before projecting
// (dpm.geom, tdpm.tesc/.tese), with the weights and triangle number by which the
// fragment reads its surface (surface_vertices.glsl).
in vec3 in_position;
out vec3 world_position_v;
out vec2 surface_weights_v;
out int surface_triangle_v;

void main() {
    int corner = gl_VertexID % 3;
    world_position_v = in_position;
    surface_weights_v = vec2(corner == 1, corner == 2);
    surface_triangle_v = gl_VertexID / 3;
}
