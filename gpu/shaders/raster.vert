#version 450 core
// Scene triangles for every raster pass (RSM faces and the camera G-buffer).
in vec3 in_position;
in vec3 in_normal;
in vec4 in_albedo;
in vec4 in_surface;
in vec4 in_transmission;
in vec4 in_specular;
in float in_metallic;
uniform mat4 view_projection;
out vec3 world_position;
out vec3 world_normal;
out vec4 surface_albedo;
out vec4 surface_coord;
out vec4 surface_transmission;
out vec4 surface_specular;
out float surface_metallic;
flat out int surface_triangle;  // the triangle's number in the vertex buffer (a culled draw's
                                 // gl_PrimitiveID restarts at each cluster)

void main() {
    world_position = in_position;
    world_normal = in_normal;
    surface_albedo = in_albedo;
    surface_coord = in_surface;
    surface_transmission = in_transmission;
    surface_specular = in_specular;
    surface_metallic = in_metallic;
    surface_triangle = gl_VertexID / 3;
    gl_Position = view_projection * vec4(in_position, 1.0);
}
