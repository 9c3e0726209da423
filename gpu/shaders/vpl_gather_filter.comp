#version 450 core
// Puts the interleaved subsets of vpl_gather_pixels.comp back together: every pixel averages
// the INTERLEAVE x INTERLEAVE block of gathered sums around it (one of each subset), each
// weighted by how alike its surface is (depth and normal), so light does not bleed across
// edges.
#include "gbuffer.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform readonly image2D gathered;
layout(rgba32f, binding = 1) uniform writeonly image2D filtered;
uniform vec3 camera_position;
uniform float depth_tolerance;  // a neighbour this far off the pixel's plane, over its distance, weighs half

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(filtered);
    if (any(greaterThanEqual(pixel, size))) return;
    vec3 p, n, albedo;
    if (!gbuffer_surface(pixel, p, n, albedo)) {
        imageStore(filtered, pixel, vec4(0.0));
        return;
    }
    float distance_here = distance(p, camera_position);
    vec3 sum = vec3(0.0);
    float total = 0.0;
    ivec2 low = pixel - INTERLEAVE / 2;
    for (int dy = 0; dy < INTERLEAVE; ++dy) {
        for (int dx = 0; dx < INTERLEAVE; ++dx) {
            ivec2 other = clamp(low + ivec2(dx, dy), ivec2(0), size - 1);
            vec3 q, m, other_albedo;
            if (!gbuffer_surface(other, q, m, other_albedo)) continue;
            float depth_weight = 1.0 / (1.0 + abs(dot(q - p, n)) / (depth_tolerance * distance_here));
            float weight = depth_weight * pow(max(dot(n, m), 0.0), 8.0);
            sum += weight * imageLoad(gathered, other).rgb;
            total += weight;
        }
    }
    imageStore(filtered, pixel, vec4(total > 0.0 ? sum / total : vec3(0.0), 0.0));
}
