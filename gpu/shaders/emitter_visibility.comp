#version 450 core
// The emitters' shadows (gpu/emitter_shadows.py): the emitter grid's light at a pixel
// times the share of it that reaches the pixel past occluders, the ratio of a light
// grid's irradiance with visibility to the same without (light_grid_gather.comp,
// UNSHADOWED) looked up as the indirect light is, both luminances through one lookup's
// marches (light_grid_lookup.glsl PAIRED).
#include "common.glsl"
#include "gbuffer.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
#define GRIDS (LEVELS * PHASES)
#define PAIRED
uniform vec3 grid_origins[GRIDS];
uniform float cell_sizes[GRIDS];
uniform int grid_size;
uniform vec3 luminance_weights;
#include "light_grid_lookup.glsl"
#include "light_grid_levels.glsl"
layout(rgba32f, binding = 0) uniform image2D irradiance;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(irradiance)))) return;
    vec3 p, n, albedo;
    if (!gbuffer_surface(pixel, p, n, albedo)) return;
    vec3 light = levels_irradiance(p, n, gbuffer_view(pixel, p));  // shadowed in r, unshadowed in g
    float reaching = light.g > 0.0 ? clamp(light.r / light.g, 0.0, 1.0) : 1.0;
    imageStore(irradiance, pixel, imageLoad(irradiance, pixel) * reaching);
}
