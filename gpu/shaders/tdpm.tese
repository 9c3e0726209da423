#version 450 core
// New vertices interpolate the *world* position linearly; the geometry shader then
// projects every one exactly with eq. 3.
layout(triangles, equal_spacing, ccw) in;
in vec3 world_position_c[];
in vec2 surface_weights_c[];
patch in int surface_triangle_c;
out vec3 world_position_v;
out vec2 surface_weights_v;
out int surface_triangle_v;

void main() {
    vec3 w = gl_TessCoord;
    world_position_v = w.x * world_position_c[0] + w.y * world_position_c[1] + w.z * world_position_c[2];
    surface_weights_v = w.x * surface_weights_c[0] + w.y * surface_weights_c[1] + w.z * surface_weights_c[2];
    surface_triangle_v = surface_triangle_c;
}
