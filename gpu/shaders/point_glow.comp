#version 450 core
// The point emitters' glow (emitter_glow.glsl) without the rasteriser, whose units are few
// on the H100 and H200 (docs/performance.md, "An emitter frame"): a disc adds its radiance into
// each pixel whose centre it covers, a speck's into the pixel it falls in with the share
// of the pixel it covers, where it lies in front of the G-buffer's depth, into sums of
// four floats a pixel (rgb and the share covered). STAGE 0: an invocation an emitter adds
// its speck or disc up to LARGEST_SPLAT pixels in radius and lists the wider discs, whose
// workgroups' dispatch command heads the list; STAGE 2: a workgroup a listed disc adds its
// pixels; STAGE 1 adds the sums into the glow image, the covered share in its alpha.
#extension GL_NV_shader_atomic_float : require
#include "common.glsl"
#include "emitter.glsl"
#include "emitter_glow.glsl"
#if STAGE == 1
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
#else
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 1) buffer Sums { float sums[]; };  // rgb and covered share a pixel, rows of image_size.x
// The wider discs' list: the workgroups of STAGE 2 (x, 1, 1: one a disc, at most
// MOST_GROUPS, each then taking every MOST_GROUPS-th), how many, then their emitters.
layout(std430, binding = 2) buffer Discs { uint disc_groups[3]; uint disc_count; uint discs[]; };
uniform sampler2D g_depth;
uniform mat4 view_projection;
const float LARGEST_SPLAT = 4.0;  // the radius in pixels of the largest disc STAGE 0 adds (81 pixels at most)
const uint MOST_GROUPS = 65535u;

void add(ivec2 pixel, int width, vec3 radiance, float covered) {
    int at = 4 * (pixel.y * width + pixel.x);
    for (int c = 0; c < 3; ++c) atomicAdd(sums[at + c], radiance[c]);
    atomicAdd(sums[at + 3], covered);
}

// Where emitter e falls on the image: its centre in pixels and its depth; false where it
// lies behind the camera or beyond the near and far planes.
bool projected(Emitter e, ivec2 size, out vec2 centre, out float depth) {
    vec4 clip = view_projection * vec4(e.position.xyz, 1.0);
    centre = vec2(0.0);
    depth = 0.0;
    if (clip.w <= 0.0) return false;
    vec3 ndc = clip.xyz / clip.w;
    centre = (ndc.xy * 0.5 + 0.5) * vec2(size);
    depth = ndc.z * 0.5 + 0.5;
    return abs(ndc.z) <= 1.0;
}

// The pixels a disc of `radius` pixels at `centre` may cover: those of the square a point
// of its side would cover, within the image.
void disc_box(vec2 centre, float radius, ivec2 size, out ivec2 low, out ivec2 high) {
    float side = ceil(2.0 * radius + 1.0);
    low = max(ivec2(ceil(centre - 0.5 * side - 0.5)), ivec2(0));
    high = min(ivec2(floor(centre + 0.5 * side - 0.5)), size - 1);
}

// Add the disc into `pixel` where it covers the pixel's centre in front of the G-buffer.
void add_disc_pixel(ivec2 pixel, vec2 centre, float radius, float depth, vec3 radiance, int width) {
    if (length(vec2(pixel) + 0.5 - centre) <= radius && depth < texelFetch(g_depth, pixel, 0).r)
        add(pixel, width, radiance, 1.0);
}

#if STAGE == 0
uniform int emitter_count;
uniform int first_emitter;  // this dispatch's first (a dispatch reaches 65,535 workgroups)

void main() {
    int index = first_emitter + int(gl_GlobalInvocationID.x);
    if (index >= emitter_count) return;
    Emitter e = emitters[index];
    if (e.position.w <= 0.0) return;
    ivec2 size = textureSize(g_depth, 0);
    vec2 centre;
    float depth;
    if (!projected(e, size, centre, depth)) return;
    float radius = glow_radius(e);
    if (radius >= LARGEST_SPLAT) {
        uint slot = atomicAdd(disc_count, 1u);
        discs[slot] = uint(index);
        atomicMax(disc_groups[0], min(slot + 1u, MOST_GROUPS));
        return;
    }
    vec3 radiance = glow_radiance(e, radius);
    if (radius < 0.5) {
        if (any(lessThan(centre, vec2(0.0))) || any(greaterThan(centre, vec2(size)))) return;
        ivec2 pixel = min(ivec2(floor(centre)), size - 1);
        if (depth < texelFetch(g_depth, pixel, 0).r) add(pixel, size.x, radiance, PI * radius * radius);
        return;
    }
    ivec2 low, high;
    disc_box(centre, radius, size, low, high);
    for (int y = low.y; y <= high.y; ++y)
        for (int x = low.x; x <= high.x; ++x) add_disc_pixel(ivec2(x, y), centre, radius, depth, radiance, size.x);
}
#else
void main() {
    ivec2 size = textureSize(g_depth, 0);
    for (uint d = gl_WorkGroupID.x; d < disc_count; d += gl_NumWorkGroups.x) {
        Emitter e = emitters[discs[d]];
        vec2 centre;
        float depth;
        projected(e, size, centre, depth);
        float radius = glow_radius(e);
        vec3 radiance = glow_radiance(e, radius);
        ivec2 low, high;
        disc_box(centre, radius, size, low, high);
        int width = high.x - low.x + 1;
        int pixels = width * (high.y - low.y + 1);
        for (int k = int(gl_LocalInvocationID.x); k < pixels && width > 0; k += 64)
            add_disc_pixel(low + ivec2(k % width, k / width), centre, radius, depth, radiance, size.x);
    }
}
#endif
#endif
