#version 450 core
// New vertices interpolate the *world* position linearly; the geometry shader then
// projects every one exactly with eq. 3.
layout(triangles, equal_spacing, ccw) in;
in vec3 world_position_c[];
in vec3 world_normal_c[];
in vec4 surface_albedo_c[];
in vec4 surface_coord_c[];
in vec4 surface_transmission_c[];
in vec4 surface_specular_c[];
in float surface_metallic_c[];
out vec3 world_position_v;
out vec3 world_normal_v;
out vec4 surface_albedo_v;
out vec4 surface_coord_v;
out vec4 surface_transmission_v;
out vec4 surface_specular_v;
out float surface_metallic_v;

void main() {
    vec3 w = gl_TessCoord;
    world_position_v = w.x * world_position_c[0] + w.y * world_position_c[1] + w.z * world_position_c[2];
    world_normal_v = w.x * world_normal_c[0] + w.y * world_normal_c[1] + w.z * world_normal_c[2];
    surface_albedo_v = w.x * surface_albedo_c[0] + w.y * surface_albedo_c[1] + w.z * surface_albedo_c[2];
    surface_coord_v = w.x * surface_coord_c[0] + w.y * surface_coord_c[1] + w.z * surface_coord_c[2];
    surface_transmission_v = w.x * surface_transmission_c[0] + w.y * surface_transmission_c[1] + w.z * surface_transmission_c[2];
    surface_specular_v = w.x * surface_specular_c[0] + w.y * surface_specular_c[1] + w.z * surface_specular_c[2];
    surface_metallic_v = w.x * surface_metallic_c[0] + w.y * surface_metallic_c[1] + w.z * surface_metallic_c[2];
}
