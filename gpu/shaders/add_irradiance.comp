#version 450 core
// Adds albedo / pi times a gathered irradiance (vpl_gather_filter.comp's image) into the
// direct image: the direct light of emissive surfaces (gpu/surface_emitters.py).
#include "common.glsl"
#include "gbuffer.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform image2D direct;
uniform sampler2D gathered;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(direct)))) return;
    vec3 p, n, albedo;
    if (!gbuffer_surface(pixel, p, n, albedo)) return;
    vec4 before = imageLoad(direct, pixel);
    imageStore(direct, pixel, before + vec4(albedo / PI * texelFetch(gathered, pixel, 0).rgb, 0.0));
}
