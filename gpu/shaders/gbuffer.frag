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
#include "surface_vertices.glsl"
#ifdef SHUT_SIDES
layout(std430, binding = 0) readonly buffer OpenSides { uint open_sides[]; };  // a byte a triangle
#endif
uniform vec4 camera_eye;  // the camera's position, w 1; orthographic: the direction toward it, w 0
layout(location = 0) out uvec4 out_surface;
layout(location = 1) out uvec4 out_specular;

void main() {
    vec4 surface_albedo = surface_vec4(VERTEX_ALBEDO);
    vec4 surface_coord = surface_vec4(VERTEX_SURFACE);
#ifdef CUT_OUT
    if (!surface_covers(surface_albedo, surface_coord, surface_vec4(VERTEX_TINT), gl_FragCoord.xy)) discard;
#endif
    vec3 n = normalize(surface_vec3(VERTEX_NORMAL));
#ifdef SHUT_SIDES
    uint sides = open_sides[surface_triangle >> 2] >> (8 * (surface_triangle & 3));
    if ((sides & (gl_FrontFacing ? 1u : 2u)) == 0u) {  // FRONT: the side its winding faces
        out_surface = gbuffer_pack(n, vec3(0.0));
        out_specular = gbuffer_pack_specular(vec3(0.0), 1.0, 0.0);
        return;
    }
#endif
    vec3 v = normalize(camera_eye.xyz - surface_vec3(0) * camera_eye.w);
    vec4 surface_specular = surface_vec4(VERTEX_SPECULAR);
    float surface_metallic = surface_float(VERTEX_METALLIC);
    if (dot(n, v) < 0.0) n = -n;
    float kept = diffuse_under_layer(surface_specular.rgb, surface_metallic, surface_specular.a, max(dot(n, v), 1e-4));
    out_surface = gbuffer_pack(n, surface_colour(surface_albedo, surface_coord) * kept);
    out_specular = gbuffer_pack_specular(surface_specular.rgb, surface_specular.a, surface_metallic);
}
