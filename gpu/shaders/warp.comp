#version 450 core
// WDPM: fixed-point-iteration backward warping of a dual paraboloid RSM (thesis eq. 4-7).
// For each target texel t, find the source texel x whose stored world position projects
// exactly onto t: x <- x + lambda * (t - P(W(x))), lambda damped by alpha while the error
// exceeds a texel (eq. 5); stop at half a texel (eq. 6) or when the error stops changing
// (eq. 7, Scarborough); restart inside the box of the last two steps on background.
#include "paraboloid.glsl"
#include "rsm_texel.glsl"
#define STATUS_BACKGROUND 0
#define STATUS_CONVERGED 1
#define STATUS_APPROXIMATE 2
#define STATUS_FAILED 3
#define MAX_ITERATIONS 64
#define FAILED_FILL_TEXELS 2.0
layout(local_size_x = 8, local_size_y = 8) in;
uniform sampler2D source_position;
uniform sampler2D source_normal;
uniform sampler2D source_flux;
layout(rgba32f, binding = 0) uniform writeonly image2D target_position;
layout(rgba32f, binding = 1) uniform writeonly image2D target_normal;
layout(rgba32f, binding = 2) uniform writeonly image2D target_flux;
layout(r32i, binding = 3) uniform writeonly iimage2D target_status;  // status | restarted << 2 | iterations << 4
layout(std430, binding = 0) buffer Counts { int counts[]; };  // 4 statuses, then iterations 0..64
uniform mat4 hemisphere_view;
uniform ivec2 face_origin;
uniform int resolution;
uniform float alpha;
uniform int iterations;
uniform float scarborough_tolerance;  // percent: 0.5 * 10^(2 - n)
uniform int approximate_from;         // eq. 7 is checked late: from this iteration on
uniform vec2 restart_pattern[8];

shared int local_counts[4 + MAX_ITERATIONS + 1];

ivec2 texel_of(vec2 x) {
    return face_origin + clamp(ivec2(floor(x * float(resolution))), ivec2(0), ivec2(resolution - 1));
}

vec2 map_uv(vec3 world) {
    return paraboloid_project((hemisphere_view * vec4(world, 1.0)).xyz) * 0.5 + 0.5;
}

void main() {
    int lane = int(gl_LocalInvocationIndex);
    for (int i = lane; i < 4 + MAX_ITERATIONS + 1; i += 64) local_counts[i] = 0;
    barrier();

    ivec2 local = ivec2(gl_GlobalInvocationID.xy);
    bool inside_map = local.x < resolution && local.y < resolution;
    vec2 t = (vec2(local) + 0.5) / float(resolution);
    int status = STATUS_BACKGROUND;
    int used = 0;
    bool restarted = false;
    ivec2 chosen = ivec2(-1);  // the accepted source texel (converged or approximate)
    if (inside_map && dot(t * 2.0 - 1.0, t * 2.0 - 1.0) <= 1.0) {
        float half_texel = 0.5 / float(resolution);
        float lambda = 1.0;
        float previous_error = -1.0;
        bool seen_geometry = false;
        float best_error = 1e30;
        ivec2 best = ivec2(-1);
        vec2 x = t;
        vec2 x_previous = t;
        int restarts = 0;
        for (int k = 0; k < iterations; ++k) {
            used = k + 1;
            ivec2 texel = texel_of(x);
            vec4 w = texelFetch(source_position, texel, 0);
            if (w.w <= 0.0) {
                // Background: W is unknown. Restart at a fixed Poisson-disk point of the
                // box spanned by the last two steps (at least a texel wide).
                vec2 low = min(x_previous, x) - half_texel * 2.0;
                vec2 high = max(x_previous, x) + half_texel * 2.0;
                x_previous = x;
                x = clamp(mix(low, high, restart_pattern[restarts % 8]), vec2(0.0), vec2(1.0));
                restarts += 1;
                restarted = true;
                continue;
            }
            seen_geometry = true;
            vec2 e = t - map_uv(w.xyz);
            float error = length(e);
            if (error < best_error) { best_error = error; best = texel; }
            if (error < half_texel) { status = STATUS_CONVERGED; chosen = texel; break; }
            if (previous_error > 0.0 && k >= approximate_from &&
                abs(error - previous_error) / error * 100.0 < scarborough_tolerance) {
                status = STATUS_APPROXIMATE;
                chosen = texel;
                break;
            }
            previous_error = error;
            x_previous = x;
            x = clamp(x + lambda * e, vec2(0.0), vec2(1.0));
            if (error > 2.0 * half_texel) lambda *= alpha;
        }
        // Geometry seen but never accepted: failed. Filled with the best candidate when that
        // lies within FAILED_FILL_TEXELS (nearly converged), else left empty: a far
        // candidate is usually geometry that belongs beside a silhouette, not here.
        if (status == STATUS_BACKGROUND && seen_geometry) {
            status = STATUS_FAILED;
            chosen = best_error < FAILED_FILL_TEXELS / float(resolution) ? best : ivec2(-1);
        }
    }
    if (inside_map) {
        ivec2 target = face_origin + local;
        vec4 position = vec4(0.0), normal = vec4(0.0), flux = vec4(0.0);
        if (chosen.x >= 0) {
            // Flux scales with the texel's solid angle: the target's, not the source's.
            vec2 source_st = (vec2(chosen - face_origin) + 0.5) / float(resolution) * 2.0 - 1.0;
            float ratio = paraboloid_texel_solid_angle(t * 2.0 - 1.0, float(resolution)) /
                          paraboloid_texel_solid_angle(source_st, float(resolution));
            copy_rsm_texel(source_position, source_normal, source_flux, chosen, ratio, position, normal, flux);
        }
        imageStore(target_position, target, position);
        imageStore(target_normal, target, normal);
        imageStore(target_flux, target, flux);
        imageStore(target_status, target, ivec4(status | (restarted ? 4 : 0) | (used << 4)));
        atomicAdd(local_counts[status], 1);
        atomicAdd(local_counts[4 + used], 1);
    }
    barrier();
    for (int i = lane; i < 4 + MAX_ITERATIONS + 1; i += 64) {
        if (local_counts[i] != 0) atomicAdd(counts[i], local_counts[i]);
    }
}
