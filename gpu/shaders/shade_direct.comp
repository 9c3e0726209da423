#version 450 core
// Direct light of one light: Lambert and the glossy reflection (Smith-GGX with Schlick's
// Fresnel, specular.glsl), shadowed by the light's RSM distances (a light of no size: 3x3
// PCF with a normal offset; else PCSS, soft_shadow.glsl) and tinted by the transmitting
// surfaces the light passes (the map's tint at the surface's texel, with `use_tint`), added
// into the direct image. With ROOMS, only the pixels whose side of their face looks into
// the light's room (gpu/closed_meshes.py): no shadow map bias lets a lamp shut in a
// closed mesh light what stands outside it.
#include "common.glsl"
#include "light.glsl"
#include "rsm_lookup.glsl"
#include "gbuffer.glsl"
#include "specular.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
uniform sampler2D rsm_position;
uniform sampler2D rsm_tint;
uniform bool use_tint;
layout(rgba32f, binding = 0) uniform image2D direct;
uniform float texel_angle;   // 2 / resolution: a texel's width per unit distance
uniform float ortho_texel;   // sun: a texel's width in world units
uniform float shadow_bias;   // normal offset in texels
uniform bool use_inside;       // shade only the pixels within view_map_edge of inside_matrix's map
uniform bool use_outside;      // shade only the pixels beyond view_map_edge of outside_matrix's map
uniform mat4 inside_matrix;    // a sun's view maps' view-projections (gpu/shade.py VIEW_MAP_EDGE)
uniform mat4 outside_matrix;
uniform float view_map_edge;   // within this share of a map's half-width
#ifdef ROOMS
uniform int light_room;
#include "seen_room.glsl"
#endif

bool within(mat4 view_projection, vec3 p) {
    return all(lessThanEqual(abs((view_projection * vec4(p, 1.0)).xy), vec2(view_map_edge)));
}
#include "soft_shadow.glsl"

// The light's angular radius seen from `dist` away (its tangent; a sun's is its own):
// the glossy lobe is widened by it (a sized light's highlight is the lobe over its disc).
float light_spread(float dist) {
    if (shadow_shape == SHADOW_HARD) return 0.0;
    float radius = shadow_facing ? shadow_radius : sqrt(length(shadow_axis_x) * length(shadow_axis_y));
    return light_kind == LIGHT_SUN ? radius : radius / max(dist, 1e-6);
}

float visibility(vec3 p) {
    vec3 w;
    float dist;
    light_ray(p, w, dist);
    float texel_world = light_kind == LIGHT_SUN ? ortho_texel : dist * texel_angle;
    int face;
    ivec2 centre;
    if (!rsm_face_texel(p, face, centre)) return 1.0;
    float lit = 0.0;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 t = clamp(centre + ivec2(dx, dy), ivec2(0), ivec2(lookup_resolution - 1));
            float stored = texelFetch(rsm_position, lookup_origin[face] + t, 0).w;
            lit += (stored <= 0.0 || dist <= stored + 0.5 * texel_world) ? 1.0 : 0.0;
        }
    }
    return lit / 9.0;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(direct)))) return;
    vec3 p, n, albedo;
    if (!gbuffer_surface(pixel, p, n, albedo)) return;
    if ((use_inside && !within(inside_matrix, p)) || (use_outside && within(outside_matrix, p))) return;
#ifdef ROOMS
    if (seen_room(pixel) != light_room) return;
#endif
    vec3 w;
    float dist;
    light_ray(p, w, dist);
    float cos_theta = dot(n, -w);
    if (cos_theta <= 0.0) return;
    vec3 irradiance = light_irradiance(w, dist, cos_theta);
    float texel_world = light_kind == LIGHT_SUN ? ortho_texel : dist * texel_angle;
    vec3 offset = p + n * shadow_bias * texel_world;
    float v;
    if (shadow_shape == SHADOW_HARD) {
        v = visibility(offset);
    } else {
        light_ray(offset, w, dist);
        v = soft_visibility(offset, n, w, dist, pixel);
    }
    int face;
    ivec2 centre;
    if (use_tint && rsm_face_texel(p, face, centre))
        irradiance *= texelFetch(rsm_tint, lookup_origin[face] + centre, 0).rgb;
    vec3 brdf = albedo / PI;
    float metallic;
    vec4 gloss = gbuffer_specular(pixel, metallic);
    if (any(greaterThan(gloss.rgb, vec3(0.0)))) {
        float alpha = specular_alpha(gloss.a, light_spread(dist));
        brdf += ggx_brdf(n, gbuffer_view(pixel, p), -w, gloss.rgb, metallic, alpha);
    }
    vec4 previous = imageLoad(direct, pixel);
    imageStore(direct, pixel, previous + vec4(brdf * irradiance * v, 0.0));
}
