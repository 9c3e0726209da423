// Soft shadows from a light's size (PCSS, Fernando 2005): a blocker search in the light's
// map, a penumbra estimate from the light's size, then a filter of that width. Taps are
// world points on the receiver's tangent plane, each looked up through rsm_face_texel, so
// one filter works in every projection (cube faces, paraboloids, a sun's ortho map) and
// across cube faces. Needs light.glsl, rsm_lookup.glsl and `rsm_position`.
// Uniforms come from gpu/soft_shadows.py shadow_uniforms().
#include "hash.glsl"
#define SHADOW_HARD 0
#define SHADOW_ROUND 1    // a sphere's or sun's disc, a disk or ellipse area light
#define SHADOW_SQUARE 2   // a square or rectangle area light
#define MAX_SHADOW_TAPS 64

uniform int shadow_shape;
uniform bool shadow_facing;        // the light's disc faces every receiver (point, spot, sun)
uniform float shadow_radius;       // facing: the disc's radius (a sun: tan of its half-angle)
uniform vec3 shadow_axis_x;        // area: half the light's extent along +X, world units
uniform vec3 shadow_axis_y;        // area: half along +Y
uniform float shadow_search_scale; // local light: how far the blocker search reaches, (d - d_near) / d_near
uniform int shadow_taps;           // filter taps; the blocker search takes half
uniform vec2 shadow_pattern[MAX_SHADOW_TAPS];  // a Poisson set in [-1, 1]^2 (concentric square of a disc)
uniform uint shadow_seed;          // the VPL set: converging frames average other rotations

// Shirley and Chiu's concentric map of [-1, 1]^2 onto the unit disc (gpu/vpl.py concentric_disk).
vec2 shadow_concentric_disc(vec2 a) {
    if (a.x == 0.0 && a.y == 0.0) return vec2(0.0);
    float radius, angle;
    if (abs(a.x) > abs(a.y)) { radius = a.x; angle = PI / 4.0 * (a.y / a.x); }
    else { radius = a.y; angle = PI / 2.0 - PI / 4.0 * (a.x / a.y); }
    return radius * vec2(cos(angle), sin(angle));
}

// Tap i of the light's shape, moved by this pixel's toroidal shift (Cranley-Patterson).
vec2 shadow_tap(int i, vec2 shift) {
    vec2 square = mod(shadow_pattern[i] + 1.0 + shift, 2.0) - 1.0;
    return shadow_shape == SHADOW_ROUND ? shadow_concentric_disc(square) : square;
}

// The light's half-extents as seen along w, across w (world units; a sun's per unit depth).
void shadow_extent(vec3 w, out vec3 ex, out vec3 ey) {
    if (shadow_facing) {
        vec3 helper = abs(w.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
        ex = normalize(cross(helper, w)) * shadow_radius;
        ey = cross(w, ex);
    } else {
        ex = shadow_axis_x - w * dot(shadow_axis_x, w);
        ey = shadow_axis_y - w * dot(shadow_axis_y, w);
    }
}

// A blocker `stored` deep in the map, found for a tap `dist` deep: a local light's depth
// ratio (taps off the axis are deeper, their blockers too), a sun's gap along its rays.
float shadow_blocker_measure(float dist, float stored) {
    return light_kind == LIGHT_SUN ? dist - stored : stored / dist;
}

// How far the penumbra reaches per unit of the light's extent, from the blockers' mean
// measure: (d - d_b) / d_b for a local light, d - d_b for a sun.
float shadow_spread(float measure) {
    return light_kind == LIGHT_SUN ? measure : (1.0 - measure) / max(measure, 1e-6);
}

// The stored distance at the map texel of q (0: the texel saw nothing) and q's own
// distance; false where q lies outside the map (the tap is left out).
bool shadow_depths(vec3 q, out float stored, out float dist, out float texel_world) {
    vec3 w;
    light_ray(q, w, dist);
    texel_world = light_kind == LIGHT_SUN ? ortho_texel : dist * texel_angle;
    int face;
    ivec2 texel;
    if (!rsm_face_texel(q, face, texel)) return false;
    stored = texelFetch(rsm_position, lookup_origin[face] + texel, 0).w;
    return true;
}

// Visibility of receiver point p (normal offset already applied), normal n, lit along w
// from `dist` away, for pixel `pixel`: PCSS over the light's extent.
float soft_visibility(vec3 p, vec3 n, vec3 w, float dist, ivec2 pixel) {
    vec3 ex, ey;
    shadow_extent(w, ex, ey);
    float cos_theta = max(dot(n, -w), 0.05);
    uint h = hash32(uint(pixel.x) * 1973u + hash32(uint(pixel.y) * 9277u + shadow_seed * 26699u));
    vec2 shift = vec2(h & 0xffffu, h >> 16) / 65536.0 * 2.0;
    uint h2 = hash32(h);
    vec2 shift_search = vec2(h2 & 0xffffu, h2 >> 16) / 65536.0 * 2.0;
    // Blocker search: the region whose blockers can hide part of the light from p.
    float search = light_kind == LIGHT_SUN ? dist : shadow_search_scale;
    int search_taps = max(shadow_taps / 2, 1);
    float blocker_sum = 0.0;
    int blockers = 0;
    for (int i = 0; i < search_taps; ++i) {
        vec2 a = shadow_tap(i, shift_search);
        vec3 o = search * (a.x * ex + a.y * ey);
        vec3 q = p + o + w * (dot(o, n) / cos_theta);  // along the ray onto p's tangent plane
        float stored, q_dist, texel_world;
        if (shadow_depths(q, stored, q_dist, texel_world) && stored > 0.0 && q_dist > stored + 0.5 * texel_world) {
            blocker_sum += shadow_blocker_measure(q_dist, stored);
            blockers += 1;
        }
    }
    if (blockers == 0) return 1.0;
    float spread = min(shadow_spread(blocker_sum / float(blockers)), search);
    float texel_here = light_kind == LIGHT_SUN ? ortho_texel : dist * texel_angle;
    spread = max(spread, texel_here / max(max(length(ex), length(ey)), 1e-30));  // at least a texel wide
    float lit = 0.0, counted = 0.0;
    for (int i = 0; i < shadow_taps; ++i) {
        vec2 a = shadow_tap(i, shift);
        vec3 o = spread * (a.x * ex + a.y * ey);
        vec3 q = p + o + w * (dot(o, n) / cos_theta);
        float stored, q_dist, texel_world;
        if (shadow_depths(q, stored, q_dist, texel_world)) {
            lit += (stored <= 0.0 || q_dist <= stored + 0.5 * texel_world) ? 1.0 : 0.0;
            counted += 1.0;
        }
    }
    return counted > 0.0 ? lit / counted : 1.0;
}
