#version 450 core
// Dual paraboloid rasterisation (thesis eq. 3) per vertex, for triangles wholly in front
// of the rim (rim_split.comp sorts them out; the ones crossing it go through dpm.geom).
// With w = 1 the rasterizer interpolates linearly between projected vertices, like
// dpm.geom's output: that is the distortion WDPM corrects.
#include "paraboloid.glsl"
in vec3 in_position;
in vec3 in_normal;
in vec4 in_albedo;
in vec4 in_surface;
in vec4 in_transmission;
in vec4 in_specular;
in float in_metallic;
uniform mat4 hemisphere_view;  // world to hemisphere space (+z the hemisphere's axis)
uniform float near;
uniform float far;
out vec3 world_position;
out vec3 world_normal;
out vec4 surface_albedo;
out vec4 surface_coord;
out vec4 surface_transmission;
out vec4 surface_specular;
out float surface_metallic;

void main() {
    vec3 p = (hemisphere_view * vec4(in_position, 1.0)).xyz;
    gl_Position = paraboloid_clip_position(p, near, far);
    world_position = in_position;
    world_normal = in_normal;
    surface_albedo = in_albedo;
    surface_coord = in_surface;
    surface_transmission = in_transmission;
    surface_specular = in_specular;
    surface_metallic = in_metallic;
}
