#version 450 core
// World-space vertices for the stages that clip or subdivide before projecting
// (dpm.geom, tdpm.tesc/.tese).
in vec3 in_position;
in vec3 in_normal;
in vec4 in_albedo;
in vec4 in_surface;
in vec4 in_transmission;
in vec4 in_specular;
in float in_metallic;
out vec3 world_position_v;
out vec3 world_normal_v;
out vec4 surface_albedo_v;
out vec4 surface_coord_v;
out vec4 surface_transmission_v;
out vec4 surface_specular_v;
out float surface_metallic_v;

void main() {
    world_position_v = in_position;
    world_normal_v = in_normal;
    surface_albedo_v = in_albedo;
    surface_coord_v = in_surface;
    surface_transmission_v = in_transmission;
    surface_specular_v = in_specular;
    surface_metallic_v = in_metallic;
}
