#version 450 core
// Indirect light and the composite; when asked, the composite also as RGB rows, bottom row
// first, in a buffer (a viewport reads a buffer back several times faster than a texture).
// The indirect light comes from LEVELS nested grids (gpu/grids.py), each PHASES grids
// offset by a fraction of a cell (light_grid_levels.glsl). The grids
// hold an LPV (INDIRECT 0) or a light grid (INDIRECT 1); with VPL gathering (INDIRECT 2)
// the irradiance is the pixel's own, gathered before. A still image averages VPL sets, each
// seen through another point of the pixel (gpu/pixel_filter.py): the indirect, direct mean
// and combined images hold the means of the `accumulated` sets before this one, which this
// set's join (the direct image is this set's alone). The combined
// image's alpha is the pixel's coverage: 1 where it sees a surface or an emitter's glow,
// 0 where it sees the background (Film Transparent); the viewport's rows stay opaque.
// There the world's background map (gpu/world.py, equirectangular) is seen along the ray.
// With REFLECTIONS the light glossy surfaces reflect (reflections.glsl) goes into the
// reflections image (its mean over the sets, as the others) and the composite. With ROOMS
// (a light grid) each lookup reads only the cells in the room of the side it looks up.
#include "common.glsl"
#include "gbuffer.glsl"
#include "occupancy.glsl"  // here, not in a branch below: an include is expanded once, where first named
#include "occupancy_volumes.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
#define GRIDS (LEVELS * PHASES)
uniform vec3 grid_origins[GRIDS];
uniform float cell_sizes[GRIDS];
uniform int grid_size;
#if INDIRECT == 0
#include "lpv_lookup.glsl"
#elif INDIRECT == 1
#include "light_grid_lookup.glsl"
#else
#include "vpl_gather_lookup.glsl"
#endif
#if INDIRECT != 2
#include "light_grid_levels.glsl"
#endif
#ifdef ROOMS
#include "seen_room.glsl"
#endif
#ifdef MARCH_ESCAPE
#include "levels_march.glsl"
#endif
layout(rgba32f, binding = 0) uniform readonly image2D direct;
layout(rgba32f, binding = 1) uniform image2D indirect;
layout(rgba32f, binding = 2) uniform image2D combined;
layout(rgba32f, binding = 4) uniform image2D direct_mean;
layout(std430, binding = 0) writeonly buffer Display { float display_rows[]; };  // RGB a pixel (gpu/shade.py DISPLAY_CHANNELS)
uniform bool write_display;
uniform float intensity;
uniform int accumulated;
uniform bool add_glow;   // the emissive surfaces' and point emitters' own radiance, and the share they cover (shade.py render_glow)
layout(rgba32f, binding = 3) uniform readonly image2D glow;
uniform bool add_world;  // the world seen where no surface is
uniform sampler2D world_background;
layout(rgba32f, binding = 5) uniform image2D reflections;

// The irradiance at the surface point p (normal n) seen at `pixel` from the unit direction
// `toward`; with a VPL gather the pixel's own whatever n is (it knows no other).
vec3 surface_irradiance(ivec2 pixel, vec3 p, vec3 n, vec3 toward) {
#if INDIRECT == 2
    return texelFetch(gathered, pixel, 0).rgb;
#else
    return levels_irradiance(p, n, toward);
#endif
}
#ifdef REFLECTIONS
#include "specular.glsl"
#include "reflections.glsl"
#endif

// The world's radiance along the unit direction `d`, as Blender's Environment Texture maps
// it (the texture's first row looks straight down).
vec3 world_radiance(vec3 d) {
    vec2 uv = vec2(0.5 - atan(d.y, d.x) / (2.0 * PI), 1.0 - acos(clamp(d.z, -1.0, 1.0)) / PI);
    return textureLod(world_background, uv, 0.0).rgb;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(indirect)))) return;
    vec4 direct_light = imageLoad(direct, pixel);
    vec3 light = vec3(0.0);
    vec3 p, n, albedo;
    bool surface = gbuffer_surface(pixel, p, n, albedo);
    // every grid lookup of the pixel in one loop: its own, then its reflection's hit
    int lookups = surface ? 1 : 0;
    ivec2 pixels[2] = ivec2[2](pixel, pixel);
    vec3 points[2] = vec3[2](p, p);
    vec3 normals[2] = vec3[2](n, n);
    vec3 weights[2] = vec3[2](albedo / PI * intensity, vec3(0.0));
    vec3 reflected = vec3(0.0), own_reflected = vec3(0.0);
#ifdef REFLECTIONS
    float metallic;
    vec4 gloss = surface ? gbuffer_specular(pixel, metallic) : vec4(0.0);
    if (any(greaterThan(gloss.rgb, vec3(0.0)))) {
        Reflection reflection = trace_reflection(pixel, p, n, gloss, metallic);
        reflected = reflection.light;
        own_reflected = reflection.own;
        if (reflection.seen) {
            pixels[1] = reflection.pixel;
            points[1] = reflection.point;
            normals[1] = reflection.normal;
            weights[1] = reflection.weight;
            lookups = 2;
        }
    }
#endif
    for (int k = 0; k < lookups; ++k) {
        vec3 toward = k == 0 ? gbuffer_view(pixel, p) : normalize(p - points[1]);  // from the camera, the mirror
#ifdef ROOMS
        lookup_room = seen_room(pixels[k]);
#endif
        vec3 irradiance = surface_irradiance(pixels[k], points[k], normals[k], toward);
        if (k == 0) {
            light = weights[0] * irradiance;
            reflected += own_reflected * irradiance;
        } else {
            reflected += weights[1] * irradiance;
        }
    }
    // the glow the pixel sees, and the share of it point emitters cover in front of its surface
    vec4 glowing = add_glow ? imageLoad(glow, pixel) : vec4(0.0);
    float shown = 1.0 - clamp(glowing.a, 0.0, 1.0);
    light *= shown;
    reflected *= shown;
    direct_light.rgb *= shown;
    float weight = 1.0 / float(accumulated + 1);  // this set's in the mean
#ifdef REFLECTIONS
    imageStore(reflections, pixel, vec4(accumulated > 0 ? mix(imageLoad(reflections, pixel).rgb, reflected, weight)
                                                        : reflected, 1.0));
#endif
    vec3 indirect_mean = accumulated > 0 ? mix(imageLoad(indirect, pixel).rgb, light, weight) : light;
    imageStore(indirect, pixel, vec4(indirect_mean, 1.0));
    vec3 direct_average = accumulated > 0 ? mix(imageLoad(direct_mean, pixel).rgb, direct_light.rgb, weight)
                                          : direct_light.rgb;
    imageStore(direct_mean, pixel, vec4(direct_average, 1.0));
    vec4 composite = vec4(direct_light.rgb + light + reflected, 1.0);
    float coverage = surface ? 1.0 : 0.0;
    if (!surface && add_world)
        composite.rgb += shown * world_radiance(normalize(gbuffer_unproject(pixel, 1.0) - gbuffer_unproject(pixel, 0.0)));
    composite.rgb += glowing.rgb;
    if (any(greaterThan(glowing.rgb, vec3(0.0)))) coverage = 1.0;
    vec4 mean = vec4(composite.rgb, coverage);
    if (accumulated > 0) mean = mix(imageLoad(combined, pixel), mean, weight);
    imageStore(combined, pixel, mean);
    if (write_display) {
        int at = 3 * (pixel.y * imageSize(combined).x + pixel.x);
        display_rows[at] = mean.r;
        display_rows[at + 1] = mean.g;
        display_rows[at + 2] = mean.b;
    }
}
