#version 450 core
// Scene triangles for every raster pass (RSM faces and the camera G-buffer).
in vec3 in_position;
in vec3 in_normal;
in vec3 in_albedo;
in vec3 in_surface;
uniform mat4 view_projection;
out vec3 world_position;
out vec3 world_normal;
out vec3 surface_albedo;
out vec3 surface_coord;

void main() {
    world_position = in_position;
    world_normal = in_normal;
    surface_albedo = in_albedo;
    surface_coord = in_surface;
    gl_Position = view_projection * vec4(in_position, 1.0);
}
