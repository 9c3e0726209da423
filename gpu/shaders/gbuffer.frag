#version 450 core
// Camera G-buffer: the depth, and per pixel the normal turned toward the camera (surfaces
// are two-sided) and the albedo (the image's where it has one) darkened by the glossy layer
// over it toward the camera (specular.glsl), packed into one texel (gbuffer.glsl), and the
// glossy reflection (F0, roughness, metallic) in a second.
// With CUT_OUT a pixel the surface does not cover (surface.glsl) shows what is behind it.
// With SHUT_SIDES the side of a solid's face that looks into it (gpu/closed_meshes.py: no
// light reaches it) is black: a camera inside a solid sees what Cycles shows there.
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
#ifdef SHUT_SIDES
layout(std430, binding = 0) readonly buffer OpenSides { uint open_sides[]; };  // a byte a triangle
flat in int surface_triangle;
#endif
uniform vec4 camera_eye;  // the camera's position, w 1; orthographic: the direction toward it, w 0
layout(location = 0) out uvec4 out_surface;
layout(location = 1) out uvec4 out_specular;

void main() {
#ifdef CUT_OUT
    if (!surface_covers(surface_albedo, surface_coord, surface_transmission, gl_FragCoord.xy)) discard;
#endif
    vec3 n = normalize(world_normal);
#ifdef SHUT_SIDES
    uint sides = open_sides[surface_triangle >> 2] >> (8 * (surface_triangle & 3));
    if ((sides & (gl_FrontFacing ? 1u : 2u)) == 0u) {  // FRONT: the side its winding faces
        out_surface = gbuffer_pack(n, vec3(0.0));
        out_specular = gbuffer_pack_specular(vec3(0.0), 1.0, 0.0);
        return;
    }
#endif
    vec3 v = normalize(camera_eye.xyz - world_position * camera_eye.w);
    if (dot(n, v) < 0.0) n = -n;
    float kept = diffuse_under_layer(surface_specular.rgb, surface_metallic, surface_specular.a, max(dot(n, v), 1e-4));
    out_surface = gbuffer_pack(n, surface_colour(surface_albedo, surface_coord) * kept);
    out_specular = gbuffer_pack_specular(surface_specular.rgb, surface_specular.a, surface_metallic);
}
