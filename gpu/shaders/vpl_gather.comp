#version 450 core
// One VPL per Poisson cell, standing for the flux of every texel in the cell: it lies at
// one of them, drawn in proportion to its flux (luminance) by weighted reservoir sampling
// seeded by the cell and the VPL pattern, and carries that texel's flux over the chance
// of drawing it. Over patterns each texel's light so stays where its surface is: a cell
// that straddles a silhouette (a sunlit wall outside a window and the floor seen through
// it) does not move the wall's light onto the floor. A cell of no flux lies at its valid
// texel nearest the cell's sample point.
// With `exclude`, texels whose surface lies in the box [exclude_low, exclude_high] count
// for nothing (a sun's far field, whose near part another map samples). Each VPL carries
// its light's room (rooms.glsl).
// With `glossy`, the VPLs stand for what the texels' glossy layers reflect (flux.w:
// glossy_word.glsl) and the rest of their flux for nothing: each is drawn by that share,
// carries it and sends it about the mirror direction of the light's ray in a GGX lobe
// (emitter.glsl glossy_lobe) of its alpha, roughness^2, at least `least_alpha` and
// SHARPEST_ALPHA and at most 1. The lobe sends alpha^2 / (1 + alpha^2) of its flux more
// than 90° off its axis, below the surface where the light arrives along the normal: its
// flux is 1 + alpha^2 times the texel's share, so that what it sends above is that share.
// Without, they stand for the rest.
#define GROUP 64
#include "common.glsl"
#include "glossy_word.glsl"
#include "hash.glsl"
#include "light.glsl"
#include "rooms.glsl"
layout(local_size_x = GROUP) in;
uniform sampler2D rsm_position;
uniform sampler2D rsm_normal;
uniform sampler2D rsm_flux;
uniform isampler2D cell_ids;
layout(std430, binding = 0) readonly buffer Samples { vec2 sample_texel[]; };  // atlas texels
layout(std430, binding = 1) readonly buffer Bounds { ivec4 bounds[]; };
struct VPL { vec4 position; vec4 normal; vec4 flux; };  // emitter.glsl Emitter
layout(std430, binding = 2) writeonly buffer VPLs { VPL vpls[]; };

shared vec4 partial_flux[GROUP];   // rgb flux, a surfel area
shared vec2 partial_best[GROUP];   // squared distance, texel index (the fallback of no flux)
shared vec2 partial_drawn[GROUP];  // summed luminance, texel index drawn

uniform int cell_count;
uniform bool exclude;
uniform vec3 exclude_low;
uniform vec3 exclude_high;
uniform uint pattern;
uniform int room;  // the light's
uniform bool glossy;
uniform float least_alpha;  // gpu/vpl.py glossy_blur_alpha

// The share of a texel's flux (of flux.w `word`) these VPLs stand for.
float lobe_share(float word) {
    float share = glossy_word_share(word);
    return glossy ? share : 1.0 - share;
}

void main() {
    int cell = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);
    if (cell >= cell_count) return;
    int lane = int(gl_LocalInvocationID.x);
    ivec4 box = bounds[cell];
    int width = box.z - box.x + 1;
    int count = box.z >= box.x ? width * (box.w - box.y + 1) : 0;
    vec2 target = sample_texel[cell];
    vec4 sum = vec4(0.0);
    vec2 best = vec2(1e30, -1.0);
    vec2 drawn = vec2(0.0, -1.0);
    uint seed = hash32(uint(cell) ^ hash32(pattern + 0x68bc21ebu));
    for (int i = lane; i < count; i += GROUP) {
        ivec2 texel = ivec2(box.x + i % width, box.y + i / width);
        if (texelFetch(cell_ids, texel, 0).r != cell) continue;
        vec4 position = texelFetch(rsm_position, texel, 0);
        if (position.w <= 0.0) continue;
        if (exclude && all(greaterThanEqual(position.xyz, exclude_low)) && all(lessThanEqual(position.xyz, exclude_high)))
            continue;
        vec4 flux = texelFetch(rsm_flux, texel, 0);
        sum += vec4(flux.rgb, texelFetch(rsm_normal, texel, 0).w);
        float weight = (flux.r + flux.g + flux.b) * lobe_share(flux.w);
        drawn.x += weight;
        if (weight > 0.0 && hash_unit(hash32(seed ^ uint(i))) * drawn.x < weight) drawn.y = float(i);
        vec2 d = vec2(texel) + 0.5 - target;
        float dd = dot(d, d);
        if (dd < best.x) best = vec2(dd, float(i));
    }
    partial_flux[lane] = sum;
    partial_best[lane] = best;
    partial_drawn[lane] = drawn;
    barrier();
    for (int stride = GROUP / 2; stride > 0; stride /= 2) {
        if (lane < stride) {
            partial_flux[lane] += partial_flux[lane + stride];
            if (partial_best[lane + stride].x < partial_best[lane].x) partial_best[lane] = partial_best[lane + stride];
            vec2 other = partial_drawn[lane + stride];
            float total = partial_drawn[lane].x + other.x;
            uint u = hash32(seed ^ hash32(uint(lane * GROUP + stride) + 0x1b873593u));
            if (other.x > 0.0 && hash_unit(u) * total < other.x) partial_drawn[lane].y = other.y;
            partial_drawn[lane].x = total;
        }
        barrier();
    }
    if (lane == 0) {
        VPL v = VPL(vec4(0.0), vec4(0.0, 0.0, 1.0, 0.0), vec4(0.0));
        vec2 chosen = partial_drawn[0];
        int i = int(chosen.y >= 0.0 ? chosen.y : partial_best[0].y);
        if (i >= 0) {
            ivec2 texel = ivec2(box.x + i % width, box.y + i / width);
            vec3 p = texelFetch(rsm_position, texel, 0).xyz;
            vec3 n = texelFetch(rsm_normal, texel, 0).xyz;
            vec4 flux = texelFetch(rsm_flux, texel, 0);
            v.position = vec4(p, room_word(room));
            v.normal = vec4(n, partial_flux[0].a);
            // The texel's share over its chance of being drawn: its whole flux over the cell's sum
            if (chosen.y >= 0.0) v.flux = vec4(flux.rgb * (chosen.x / (flux.r + flux.g + flux.b)), 0.0);
            if (glossy) {
                vec3 w;
                float dist;
                light_ray(p, w, dist);
                float roughness = glossy_word_roughness(flux.w);
                float alpha = max(roughness * roughness, least_alpha);
                v.normal.xyz = reflect(w, n);
                alpha = clamp(alpha, SHARPEST_ALPHA, 1.0);
                v.flux = vec4(v.flux.rgb * (1.0 + alpha * alpha), -alpha);
            }
        }
        vpls[cell] = v;
    }
}
