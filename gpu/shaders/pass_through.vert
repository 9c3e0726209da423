#version 450 core
// World-space vertices for the stages that clip or subdivide before projecting
// (dpm.geom, tdpm.tesc/.tese).
in vec3 in_position;
in vec3 in_normal;
in vec3 in_albedo;
in vec3 in_surface;
out vec3 world_position_v;
out vec3 world_normal_v;
out vec3 surface_albedo_v;
out vec3 surface_coord_v;

void main() {
    world_position_v = in_position;
    world_normal_v = in_normal;
    surface_albedo_v = in_albedo;
    surface_coord_v = in_surface;
}
