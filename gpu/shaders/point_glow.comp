#version 450 core
// The point emitters' glow (emitter_glow.glsl) without the rasteriser for those smaller
// than a pixel (most of a million particles; drawn as points they took 5 ms on the H100):
// STAGE 0 adds each one's radiance into the pixel it falls in where it lies in front of
// the G-buffer's depth (the point's own depth test) and lists the larger ones for
// emitter_glow.vert's discs, whose indirect draw command heads the list; STAGE 1 adds the
// sums into the glow image.
#extension GL_NV_shader_atomic_float : require
#include "common.glsl"
#include "emitter.glsl"
#include "emitter_glow.glsl"
#if STAGE == 0
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 1) buffer Sums { float sums[]; };  // rgb a pixel, rows of image_size.x
layout(std430, binding = 2) buffer Discs { uint disc_command[5]; uint discs[]; };  // count, 1, 0, 0, 0; indices
uniform sampler2D g_depth;
uniform mat4 view_projection;
uniform int emitter_count;
uniform int first_emitter;  // this dispatch's first (a dispatch reaches 65,535 workgroups)

void main() {
    int index = first_emitter + int(gl_GlobalInvocationID.x);
    if (index >= emitter_count) return;
    Emitter e = emitters[index];
    if (e.position.w <= 0.0) return;
    vec4 clip = view_projection * vec4(e.position.xyz, 1.0);
    if (clip.w <= 0.0) return;
    float radius = glow_radius(e);
    if (radius >= 0.5) {
        discs[atomicAdd(disc_command[0], 1u)] = uint(index);
        return;
    }
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc), vec3(1.0)))) return;
    ivec2 size = textureSize(g_depth, 0);
    ivec2 pixel = min(ivec2(floor((ndc.xy * 0.5 + 0.5) * vec2(size))), size - 1);
    if (!(ndc.z * 0.5 + 0.5 < texelFetch(g_depth, pixel, 0).r)) return;
    vec3 radiance = glow_radiance(e, radius);
    int at = 3 * (pixel.y * size.x + pixel.x);
    for (int c = 0; c < 3; ++c) atomicAdd(sums[at + c], radiance[c]);
}
#else
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 1) readonly buffer Sums { float sums[]; };
layout(rgba32f, binding = 0) uniform image2D glow;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(glow);
    if (any(greaterThanEqual(pixel, size))) return;
    int at = 3 * (pixel.y * size.x + pixel.x);
    vec3 summed = vec3(sums[at], sums[at + 1], sums[at + 2]);
    if (any(greaterThan(summed, vec3(0.0)))) imageStore(glow, pixel, imageLoad(glow, pixel) + vec4(summed, 0.0));
}
#endif
