#version 450 core
// The reference for the emitter grid (gpu/emitter_grid.py): every pixel sums the
// irradiance of every point emitter, [first_emitter, first_emitter + batch) per dispatch
// (llvmpipe ends a loop nest after 65,535 iterations), the emitters shared through
// shared memory a tile at a time.
#include "common.glsl"
#include "emitter.glsl"
#include "gbuffer.glsl"
#define TILE 64
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(rgba32f, binding = 0) uniform image2D irradiance;
uniform int emitter_count;
uniform int first_emitter;
uniform int batch;

shared Emitter tile[TILE];

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    bool inside = all(lessThan(pixel, imageSize(irradiance)));
    vec3 p, n, albedo;
    bool surface = inside && gbuffer_surface(pixel, p, n, albedo);
    vec3 sum = vec3(0.0);
    int last = min(first_emitter + batch, emitter_count);
    int lane = int(gl_LocalInvocationIndex);
    for (int start = first_emitter; start < last; start += TILE) {
        if (start + lane < last) tile[lane] = emitters[start + lane];
        barrier();
        if (surface)
            for (int k = 0; k < min(TILE, last - start); ++k) {
                Emitter e = tile[k];
                if (e.position.w <= 0.0) continue;
                vec3 d = p - e.position.xyz;
                float facing = -dot(n, d) * inversesqrt(max(dot(d, d), 1e-30));
                if (facing > 0.0) sum += emitter_light(e, d) * facing;
            }
        barrier();
    }
    if (!inside) return;
    vec4 before = first_emitter == 0 ? vec4(0.0) : imageLoad(irradiance, pixel);
    imageStore(irradiance, pixel, before + vec4(sum, 0.0));
}
