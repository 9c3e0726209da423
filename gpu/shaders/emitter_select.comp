#version 450 core
// The point emitters a frame keeps, chosen on the GPU (gpu/emitter_grid.py select): each
// row's bound at the view (its intensity over its squared distance to the box the camera
// sees, at least min_distance squared) falls in one of SKIP_BINS bins by its ratio to the
// strongest, BINS_PER_OCTAVE bins an octave, weighted by itself; the weakest bins that
// together hold at most `cutoff` of the sum are skipped (gpu/frame_lights.py skip_weak is
// the lamps' form of the rule). Rows from `scene_count` on (point lights beyond the map
// budget, already chosen) are always kept. A scene row that is not finite, has a negative
// flux or area, or no flux is dropped and counted here (gpu/scene.py leaves the values of
// a million rows a frame to this pass). STAGE 0: the strongest bound; 1: the weighted
// bins; 2 (one invocation): the first skipped bin; 3: the rows (gpu/scene.py
// point_emitters: position xyz, flux rgb, area) into emitter rows, in any room (rooms.glsl),
// a skipped one with position.w 0 (a dropped one all zeros), the kept ones' count, flux and box, and the
// dropped ones' count.
#extension GL_NV_shader_atomic_float : require
#include "common.glsl"
#include "emitter.glsl"
#include "rooms.glsl"
layout(local_size_x = 64) in;  // GROUP
layout(std430, binding = 0) readonly buffer Packed { float columns[]; };
layout(std430, binding = 1) writeonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 2) buffer Selection {
    uint strongest;      // the strongest bound's bits (a positive float orders as its bits)
    uint first_skipped;  // bins from this one on are skipped
    uint kept;
    float kept_flux[3];
    uint low[3];         // the kept positions' box, as order_float keys
    uint high[3];
    uint dropped;
    float bins[SKIP_BINS];
};
uniform int emitter_count;
uniform int scene_count;
uniform int first_emitter;  // this dispatch's first (a dispatch reaches 65,535 workgroups)
uniform vec3 box_low;
uniform vec3 box_high;
uniform float min_distance_squared;
uniform float cutoff;
uniform vec3 luminance_weights;

// Each workgroup sums, bins and bounds in shared memory first and writes once: a million
// atomics on one word wait on one another, and float sums so long lose digits.
const uint GROUP = 64u;
shared float group_strongest[GROUP];
shared float group_bins[SKIP_BINS];
shared uint group_kept[GROUP];
shared vec3 group_flux[GROUP];
shared vec3 group_low[GROUP];
shared vec3 group_high[GROUP];
shared uint group_dropped[GROUP];

// Whether a scene row is one to take: every value finite (no exponent of all ones), no
// negative flux or area, and some flux.
bool sane_row(int at) {
    bool lit = false;
    for (int c = 0; c < POINT_EMITTER_COLUMNS; ++c) {
        float v = columns[at + c];
        if ((floatBitsToUint(v) & 0x7f800000u) == 0x7f800000u || (c >= 3 && v < 0.0)) return false;
        lit = lit || (c >= 3 && c < 6 && v > 0.0);
    }
    return lit;
}

vec3 position_of(int at) { return vec3(columns[at], columns[at + 1], columns[at + 2]); }
vec3 flux_of(int at) { return vec3(columns[at + 3], columns[at + 4], columns[at + 5]); }

float bound_at_view(int at) {
    vec3 p = position_of(at);
    vec3 gap = max(max(box_low - p, p - box_high), vec3(0.0));
    return dot(flux_of(at), luminance_weights) / (4.0 * PI) / max(dot(gap, gap), min_distance_squared);
}

// The bin of a bound: SKIP_BINS (beyond every bin) for none.
uint bin_of(float bound) {
    if (!(bound > 0.0)) return uint(SKIP_BINS);
    float octaves = log2(uintBitsToFloat(strongest) / bound);
    return uint(clamp(floor(octaves * float(BINS_PER_OCTAVE)), 0.0, float(SKIP_BINS - 1)));
}

// Floats as uints in their order, for atomicMin and atomicMax.
uint order_float(float f) {
    uint bits = floatBitsToUint(f);
    return (bits & 0x80000000u) != 0u ? ~bits : bits | 0x80000000u;
}

void main() {
#if STAGE == 2
    if (gl_LocalInvocationID.x != 0u) return;
    float total = 0.0;
    for (int b = 0; b < SKIP_BINS; ++b) total += bins[b];
    uint first = uint(SKIP_BINS + 1);  // nothing skipped
    if (cutoff > 0.0 && total > 0.0) {
        float dropped = 0.0;
        first = uint(SKIP_BINS);  // bounds of zero go first: they add nothing
        for (int b = SKIP_BINS - 1; b >= 0 && dropped + bins[b] <= cutoff * total; --b) {
            dropped += bins[b];
            first = uint(b);
        }
    }
    first_skipped = first;
#else
    uint lane = gl_LocalInvocationID.x;
    int index = first_emitter + int(gl_GlobalInvocationID.x);
    int at = POINT_EMITTER_COLUMNS * index;
    bool scene_row = index < min(scene_count, emitter_count);
    bool sane = !scene_row || sane_row(at);
    bool taken = scene_row && sane;
#if STAGE == 0
    float bound = taken ? bound_at_view(at) : 0.0;
    group_strongest[lane] = bound > 0.0 && !isinf(bound) ? bound : 0.0;
    barrier();
    for (uint half_size = GROUP / 2u; half_size > 0u; half_size >>= 1) {
        if (lane < half_size) group_strongest[lane] = max(group_strongest[lane], group_strongest[lane + half_size]);
        barrier();
    }
    if (lane == 0u && group_strongest[0] > 0.0) atomicMax(strongest, floatBitsToUint(group_strongest[0]));
#elif STAGE == 1
    for (uint b = lane; b < uint(SKIP_BINS); b += GROUP) group_bins[b] = 0.0;
    barrier();
    if (taken) {
        float bound = bound_at_view(at);
        uint bin = bin_of(bound);
        if (bin < uint(SKIP_BINS)) atomicAdd(group_bins[bin], bound);
    }
    barrier();
    for (uint b = lane; b < uint(SKIP_BINS); b += GROUP)
        if (group_bins[b] > 0.0) atomicAdd(bins[b], group_bins[b]);
#else
    bool row = index < emitter_count;
    bool keep = row && sane && (!scene_row || bin_of(bound_at_view(at)) < first_skipped);
    vec3 p = row && sane ? position_of(at) : vec3(0.0);
    if (row) {
        Emitter e;
        e.position = vec4(p, keep ? room_word(ANY_ROOM) : 0.0);  // its room not told
        e.normal = vec4(0.0, 0.0, 0.0, sane ? columns[at + 6] : 0.0);
        e.flux = vec4(sane ? flux_of(at) : vec3(0.0), 0.0);
        emitters[index] = e;
    }
    group_dropped[lane] = row && !sane ? 1u : 0u;
    group_kept[lane] = keep ? 1u : 0u;
    group_flux[lane] = keep ? flux_of(at) : vec3(0.0);
    group_low[lane] = keep ? p : vec3(uintBitsToFloat(0x7f800000u));    // +inf
    group_high[lane] = keep ? p : vec3(-uintBitsToFloat(0x7f800000u));  // -inf
    barrier();
    for (uint half_size = GROUP / 2u; half_size > 0u; half_size >>= 1) {
        if (lane < half_size) {
            group_kept[lane] += group_kept[lane + half_size];
            group_flux[lane] += group_flux[lane + half_size];
            group_low[lane] = min(group_low[lane], group_low[lane + half_size]);
            group_high[lane] = max(group_high[lane], group_high[lane + half_size]);
            group_dropped[lane] += group_dropped[lane + half_size];
        }
        barrier();
    }
    if (lane == 0u && group_dropped[0] > 0u) atomicAdd(dropped, group_dropped[0]);
    if (lane == 0u && group_kept[0] > 0u) {
        atomicAdd(kept, group_kept[0]);
        for (int c = 0; c < 3; ++c) {
            atomicAdd(kept_flux[c], group_flux[0][c]);
            atomicMin(low[c], order_float(group_low[0][c]));
            atomicMax(high[c], order_float(group_high[0][c]));
        }
    }
#endif
#endif
}
