#version 450 core
// Camera G-buffer: position, normal turned toward the camera (surfaces are two-sided), albedo.
in vec3 world_position;
in vec3 world_normal;
in vec3 surface_albedo;
uniform vec3 camera_position;
layout(location = 0) out vec4 out_position;  // w 1 where a surface was hit
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;

void main() {
    vec3 n = normalize(world_normal);
    if (dot(n, camera_position - world_position) < 0.0) n = -n;
    out_position = vec4(world_position, 1.0);
    out_normal = vec4(n, 0.0);
    out_albedo = vec4(surface_albedo, 1.0);
}
