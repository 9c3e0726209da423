#version 450 core
// The point emitters' glow (emitter_glow.glsl) without the rasteriser for all but the
// largest discs (a million particles a few pixels across drawn as points took 5 ms on the
// H100, whose raster units are few): STAGE 0 adds a speck's radiance into the pixel it
// falls in, and a disc's into each pixel whose centre it covers (as emitter_glow.frag
// draws it), where it lies in front of the G-buffer's depth (the point's own depth test),
// with the share of the pixel it covers (a speck's disc, or all of it), and lists the discs
// wider than LARGEST_SPLAT pixels for emitter_glow.vert, whose indirect draw command heads
// the list; STAGE 1 adds the sums into the glow image, the covered share in its alpha.
#extension GL_NV_shader_atomic_float : require
#include "common.glsl"
#include "emitter.glsl"
#include "emitter_glow.glsl"
#if STAGE == 0
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 1) buffer Sums { float sums[]; };  // rgb and covered share a pixel, rows of image_size.x
layout(std430, binding = 2) buffer Discs { uint disc_command[5]; uint discs[]; };  // count, 1, 0, 0, 0; indices
uniform sampler2D g_depth;
uniform mat4 view_projection;
uniform int emitter_count;
uniform int first_emitter;  // this dispatch's first (a dispatch reaches 65,535 workgroups)
const float LARGEST_SPLAT = 4.0;  // the radius in pixels of the largest disc added here (81 pixels at most)

void add(ivec2 pixel, int width, vec3 radiance, float covered) {
    int at = 4 * (pixel.y * width + pixel.x);
    for (int c = 0; c < 3; ++c) atomicAdd(sums[at + c], radiance[c]);
    atomicAdd(sums[at + 3], covered);
}

void main() {
    int index = first_emitter + int(gl_GlobalInvocationID.x);
    if (index >= emitter_count) return;
    Emitter e = emitters[index];
    if (e.position.w <= 0.0) return;
    vec4 clip = view_projection * vec4(e.position.xyz, 1.0);
    if (clip.w <= 0.0) return;
    float radius = glow_radius(e);
    if (radius >= LARGEST_SPLAT) {
        discs[atomicAdd(disc_command[0], 1u)] = uint(index);
        return;
    }
    vec3 ndc = clip.xyz / clip.w;
    if (abs(ndc.z) > 1.0) return;
    ivec2 size = textureSize(g_depth, 0);
    vec2 centre = (ndc.xy * 0.5 + 0.5) * vec2(size);  // in pixels
    float depth = ndc.z * 0.5 + 0.5;
    vec3 radiance = glow_radiance(e, radius);
    if (radius < 0.5) {
        if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) return;
        ivec2 pixel = min(ivec2(floor(centre)), size - 1);
        if (depth < texelFetch(g_depth, pixel, 0).r) add(pixel, size.x, radiance, PI * radius * radius);
        return;
    }
    float side = ceil(2.0 * radius + 1.0);  // the point emitter_glow.vert would draw
    ivec2 low = max(ivec2(ceil(centre - 0.5 * side - 0.5)), ivec2(0));
    ivec2 high = min(ivec2(floor(centre + 0.5 * side - 0.5)), size - 1);
    for (int y = low.y; y <= high.y; ++y)
        for (int x = low.x; x <= high.x; ++x) {
            ivec2 pixel = ivec2(x, y);
            if (length(vec2(pixel) + 0.5 - centre) <= radius && depth < texelFetch(g_depth, pixel, 0).r)
                add(pixel, size.x, radiance, 1.0);
        }
}
#else
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 1) readonly buffer Sums { float sums[]; };
layout(rgba32f, binding = 0) uniform image2D glow;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(glow);
    if (any(greaterThanEqual(pixel, size))) return;
    int at = 4 * (pixel.y * size.x + pixel.x);
    vec4 summed = vec4(sums[at], sums[at + 1], sums[at + 2], sums[at + 3]);
    if (any(greaterThan(summed, vec4(0.0)))) imageStore(glow, pixel, imageLoad(glow, pixel) + summed);
}
#endif
