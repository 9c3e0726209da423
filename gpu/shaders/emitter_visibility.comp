#version 450 core
// The emitters' shadows (gpu/emitter_shadows.py): the emitter grid's light at a pixel
// times the share of it that reaches the pixel past occluders, the ratio of a light
// grid's irradiance with visibility to the same without (light_grid_gather.comp,
// UNSHADOWED) looked up as the indirect light is. STAGE 0 writes the shadowed
// luminance; STAGE 1, its volumes bound instead, scales `irradiance` by the ratio.
#include "common.glsl"
#include "gbuffer.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
#define GRIDS (LEVELS * PHASES)
uniform vec3 grid_origins[GRIDS];
uniform float cell_sizes[GRIDS];
uniform int grid_size;
#include "light_grid_lookup.glsl"
#include "light_grid_levels.glsl"
layout(rgba32f, binding = 0) uniform image2D irradiance;
layout(rgba32f, binding = 1) uniform image2D shadowed;
uniform vec3 luminance_weights;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(irradiance)))) return;
    vec3 p, n, albedo;
    if (!gbuffer_surface(pixel, p, n, albedo)) return;
    float light = dot(levels_irradiance(p, n, gbuffer_view(pixel, p)), luminance_weights);
#if STAGE == 0
    imageStore(shadowed, pixel, vec4(light));
#else
    float reaching = light > 0.0 ? clamp(imageLoad(shadowed, pixel).r / light, 0.0, 1.0) : 1.0;
    imageStore(irradiance, pixel, imageLoad(irradiance, pixel) * reaching);
#endif
}
