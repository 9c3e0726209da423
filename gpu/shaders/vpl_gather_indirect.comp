#version 450 core
// The exact stand-in for the LPV (inject, propagate, look up): each pixel gathers the
// light of every VPL directly, each a cosine emitter of its flux, I(w) = flux / pi *
// max(0, n_v . w), or a glossy one's lobe (emitter.glsl), with no visibility; the distance squared is kept above the VPL's surfel
// area / pi, so a VPL on the pixel's own surface stays finite. Adds into `indirect`.
#include "common.glsl"
#include "emitter.glsl"
#include "gbuffer.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer VPLs { vec4 vpl_data[]; };  // position (w valid), normal (w area), flux
layout(rgba32f, binding = 0) uniform image2D indirect;
uniform int vpl_count;
uniform float intensity;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(indirect)))) return;
    vec3 p, n, albedo;
    if (!gbuffer_surface(pixel, p, n, albedo)) return;
    vec3 irradiance = vec3(0.0);
    for (int i = 0; i < vpl_count; ++i) {
        vec4 q = vpl_data[3 * i];
        if (q.w <= 0.0) continue;
        vec4 nv = vpl_data[3 * i + 1];
        vec3 d = p - q.xyz;
        float dist2 = dot(d, d);
        vec3 w = d * inversesqrt(max(dist2, 1e-30));
        vec4 flux = vpl_data[3 * i + 2];
        float intensity = emitter_intensity(Emitter(q, nv, flux), w) * max(dot(n, -w), 0.0);
        irradiance += flux.rgb * intensity / max(dist2, nv.w / PI);
    }
    vec4 previous = imageLoad(indirect, pixel);
    imageStore(indirect, pixel, previous + vec4(albedo / PI * irradiance * intensity, 0.0));
}
