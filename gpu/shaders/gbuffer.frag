#version 450 core
// Camera G-buffer: the depth, and per pixel the normal turned toward the camera (surfaces
// are two-sided) and the albedo (the image's where it has one), packed into one texel (gbuffer.glsl),
// and the glossy reflection (F0, roughness, metallic) in a second.
// With CUT_OUT a pixel the surface does not cover (surface.glsl) shows what is behind it.
#include "gbuffer.glsl"
#include "surface.glsl"
in vec3 world_position;
in vec3 world_normal;
in vec4 surface_albedo;
in vec4 surface_coord;
in vec4 surface_transmission;
in vec4 surface_specular;
in float surface_metallic;
uniform vec3 camera_position;
layout(location = 0) out uvec4 out_surface;
layout(location = 1) out uvec4 out_specular;

void main() {
#ifdef CUT_OUT
    if (!surface_covers(surface_albedo, surface_coord, surface_transmission, gl_FragCoord.xy)) discard;
#endif
    vec3 n = normalize(world_normal);
    if (dot(n, camera_position - world_position) < 0.0) n = -n;
    out_surface = gbuffer_pack(n, surface_colour(surface_albedo, surface_coord));
    out_specular = gbuffer_pack_specular(surface_specular.rgb, surface_specular.a, surface_metallic);
}
