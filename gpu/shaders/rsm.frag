#version 450 core
// Reflective shadow map texel: position, light-facing normal, reflected flux (METHOD §2):
// the diffuse and, with GLOSSY_LAYER (a scene with some F0), what the glossy layer over
// it reflects, with its share of the flux (rsm_surface.glsl).
// With CUT_OUT a texel the surface does not cover (surface.glsl) lets the light pass. With
// TINT_MAP the fourth attachment starts at 1: transmitting surfaces in front multiply it
// (passing_tint.frag). With RASTERISED a compute pass has made the texels of the small
// triangles (rim_split.comp, rsm_resolve.comp): a fragment behind theirs is dropped.
#include "rsm_surface.glsl"
layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_flux;
#ifdef TINT_MAP
layout(location = 3) out vec4 out_tint;  // rgb what the light passing transmitting surfaces is multiplied by
#endif
#ifdef RASTERISED
#include "paraboloid_raster.glsl"
layout(std430, binding = 3) readonly buffer NearestDepth { uint nearest_depth[]; };  // inverted
#endif

void main() {
#ifdef RASTERISED
    if (nearest_depth[atlas_index(ivec2(gl_FragCoord.xy))] > ~floatBitsToUint(gl_FragCoord.z)) discard;
#endif
    vec4 surface_albedo = surface_vec4(VERTEX_ALBEDO);
    SurfacePoint here = surface_point();
#ifdef CUT_OUT
    if (!surface_covers(surface_albedo, here, surface_vec4(VERTEX_TINT), gl_FragCoord.xy)) discard;
#endif
    surface_rsm_texel(surface_albedo, here, gl_FragCoord.xy, out_position, out_normal, out_flux);
#ifdef TINT_MAP
    out_tint = vec4(1.0);
#endif
}
