#version 450 core
// Indirect light from the LPV (cosine convolution, METHOD §7) and the composite; when
// asked, the composite also as RGBA rows, bottom row first, in a buffer (a viewport reads
// a buffer back several times faster than a texture).
#include "common.glsl"
#include "gbuffer.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
// PHASES grids, each offset by a fraction of a cell: their lookups are averaged.
uniform sampler3D lpv_r[PHASES];
uniform sampler3D lpv_g[PHASES];
uniform sampler3D lpv_b[PHASES];
layout(rgba32f, binding = 0) uniform readonly image2D direct;
layout(rgba32f, binding = 1) uniform writeonly image2D indirect;
layout(rgba32f, binding = 2) uniform writeonly image2D combined;
layout(std430, binding = 0) writeonly buffer Display { vec4 display_rows[]; };
uniform bool write_display;
uniform vec3 grid_origins[PHASES];
uniform float cell_size;
uniform int grid_size;
uniform float intensity;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(indirect)))) return;
    vec4 direct_light = imageLoad(direct, pixel);
    vec3 light = vec3(0.0);
    vec3 p, n, albedo;
    if (gbuffer_surface(pixel, p, n, albedo)) {
        vec4 lobe = cos_lobe(-n);
        vec3 irradiance = vec3(0.0);
        for (int phase = 0; phase < PHASES; ++phase) {
            vec3 uvw = (p + 0.5 * cell_size * n - grid_origins[phase]) / (cell_size * float(grid_size));
            irradiance += max(vec3(dot(texture(lpv_r[phase], uvw), lobe), dot(texture(lpv_g[phase], uvw), lobe),
                                   dot(texture(lpv_b[phase], uvw), lobe)), 0.0);
        }
        // Intensity per cell to irradiance: divide by the cell's face area.
        irradiance /= float(PHASES) * cell_size * cell_size;
        light = albedo / PI * irradiance * intensity;
    }
    imageStore(indirect, pixel, vec4(light, 1.0));
    vec4 composite = vec4(direct_light.rgb + light, 1.0);
    imageStore(combined, pixel, composite);
    if (write_display) display_rows[pixel.y * imageSize(combined).x + pixel.x] = composite;
}
