#version 450 core
// Reflective shadow map texel: position, light-facing normal, reflected flux (METHOD §2):
// the diffuse and, with GLOSSY_LAYER (a scene with some F0), what the glossy layer over
// it sends on (specular.glsl bounce_colour).
// With CUT_OUT a texel the surface does not cover (surface.glsl) lets the light pass. With
// TINT_MAP the fourth attachment starts at 1: transmitting surfaces in front multiply it
// (passing_tint.frag).
#include "common.glsl"
#include "light.glsl"
#include "paraboloid.glsl"
#include "specular.glsl"
#include "surface.glsl"
#include "surface_vertices.glsl"
#define PROJECTION_CUBE 0
#define PROJECTION_PARABOLOID 1
#define PROJECTION_ORTHO 2
uniform vec2 face_origin;        // this face's lower-left texel in the atlas
uniform float resolution;        // texels along one side of a face
uniform float ortho_texel_area;  // sun: the area one texel covers across the beam
uniform int projection_kind;
layout(location = 0) out vec4 out_position;  // xyz world, w shadow distance (0: empty)
layout(location = 1) out vec4 out_normal;    // xyz normal toward the light, w surfel area
layout(location = 2) out vec4 out_flux;      // rgb reflected flux in W, w 1
#ifdef TINT_MAP
layout(location = 3) out vec4 out_tint;      // rgb what the light passing transmitting surfaces is multiplied by
#endif

void main() {
    vec4 surface_albedo = surface_vec4(VERTEX_ALBEDO);
    SurfacePoint here = surface_point();
#ifdef CUT_OUT
    if (!surface_covers(surface_albedo, here, surface_vec4(VERTEX_TINT), gl_FragCoord.xy)) discard;
#endif
    vec3 world_position = surface_vec3(0);
    vec3 w;
    float dist;
    light_ray(world_position, w, dist);
    vec3 n = normalize(surface_vec3(VERTEX_NORMAL));
    if (dot(n, w) > 0.0) n = -n;
    float cos_receiver = max(abs(dot(n, w)), 0.05);
    vec3 power;
    float area;
    if (light_kind == LIGHT_SUN) {
        power = light_peak * ortho_texel_area;
        area = ortho_texel_area / cos_receiver;
    } else {
        // The texel's solid angle from its map coordinates (METHOD §2).
        vec2 uv = (gl_FragCoord.xy - face_origin) / resolution * 2.0 - 1.0;
        float solid_angle = projection_kind == PROJECTION_PARABOLOID
            ? paraboloid_texel_solid_angle(uv, resolution)
            : cube_texel_solid_angle(uv, resolution);
        power = light_intensity(w) * solid_angle;
        area = dist * dist * solid_angle / cos_receiver;
    }
    out_position = vec4(world_position, max(dist, 1e-30));
    out_normal = vec4(n, area);
    vec3 colour = surface_colour(surface_albedo, here);
#ifdef GLOSSY_LAYER
    vec4 specular = surface_vec4(VERTEX_SPECULAR);  // F0 rgb, roughness
    colour = bounce_colour(colour, specular.rgb, surface_float(VERTEX_METALLIC), specular.a, abs(dot(n, w)));
#endif
    out_flux = vec4(colour * power, 1.0);
#ifdef TINT_MAP
    out_tint = vec4(1.0);
#endif
}
