#version 450 core
// Camera G-buffer: the depth, and per pixel the normal turned toward the camera (surfaces
// are two-sided) and the albedo (the image's where it has one) darkened by the glossy layer
// over it toward the camera (specular.glsl), packed into one texel (gbuffer.glsl), and the
// glossy reflection (F0, roughness, metallic) in a second.
// With CUT_OUT a pixel the surface does not cover (surface.glsl) shows what is behind it.
#include "gbuffer.glsl"
#include "common.glsl"
#include "specular.glsl"
#include "surface.glsl"
in vec3 world_position;
in vec3 world_normal;
in vec4 surface_albedo;
in vec4 surface_coord;
in vec4 surface_transmission;
in vec4 surface_specular;
in float surface_metallic;
uniform vec4 camera_eye;  // the camera's position, w 1; orthographic: the direction toward it, w 0
layout(location = 0) out uvec4 out_surface;
layout(location = 1) out uvec4 out_specular;

void main() {
#ifdef CUT_OUT
    if (!surface_covers(surface_albedo, surface_coord, surface_transmission, gl_FragCoord.xy)) discard;
#endif
    vec3 n = normalize(world_normal);
    vec3 v = normalize(camera_eye.xyz - world_position * camera_eye.w);
    if (dot(n, v) < 0.0) n = -n;
    float kept = diffuse_under_layer(surface_specular.rgb, surface_metallic, surface_specular.a, max(dot(n, v), 1e-4));
    out_surface = gbuffer_pack(n, surface_colour(surface_albedo, surface_coord) * kept);
    out_specular = gbuffer_pack_specular(surface_specular.rgb, surface_specular.a, surface_metallic);
}
