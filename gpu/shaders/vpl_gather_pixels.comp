#version 450 core
// VPL gathering (gpu/vpl_gather.py): every pixel of the camera's G-buffer sums the
// irradiance of the VPLs that see it, through a march in the occupancy of every grid level. Interleaved: the
// pixel at (x, y) of each INTERLEAVE x INTERLEAVE block takes every INTERLEAVE²-th VPL
// from its own offset (shifted by the VPL set's number: the VPLs are in the order of their
// Poisson cells, so a fixed offset would give each pixel of a block its own lattice of
// places to be lit from, a pattern that averaging sets would keep), its sum scaled by INTERLEAVE² (vpl_gather_filter.comp puts the
// block's subsets back together). One dispatch adds the VPLs [first, first + batch) of
// one set to what the ones before left: llvmpipe ends a loop nest after 65,535 iterations.
// With ROOMS a pixel gathers only the emitters that light the room of the side it sees
// (rooms.glsl).
#include "common.glsl"
#include "gbuffer.glsl"
#include "emitter.glsl"
#include "levels_march.glsl"
#ifdef ROOMS
#include "seen_room.glsl"
#endif
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(rgba32f, binding = 0) uniform image2D gathered;
uniform int emitter_count;
uniform int first_emitter;
uniform int batch;
uniform bool accumulate;
uniform int subset_shift;  // the VPL set's: a pixel's subset moves on from set to set
uniform float held_bound;  // the later bounces' points' bound (emitter.glsl shared_emitter_light), never shrunk
const float OFF_SURFACE = 1.5;     // finest voxels off the pixel's surface where its marches end

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(gathered)))) return;
    vec3 p, n, albedo;
    vec3 sum = vec3(0.0);
    if (gbuffer_surface(pixel, p, n, albedo)) {
        int subset = ((pixel.y % INTERLEAVE) * INTERLEAVE + pixel.x % INTERLEAVE + subset_shift)
                     % (INTERLEAVE * INTERLEAVE);
        vec3 from_pixel = p + OFF_SURFACE * level_voxels[0] * n;
        int last = min(first_emitter + batch, emitter_count);
#ifdef ROOMS
        int room = seen_room(pixel);
#endif
        int start = first_emitter + (subset - first_emitter % (INTERLEAVE * INTERLEAVE) + INTERLEAVE * INTERLEAVE)
                    % (INTERLEAVE * INTERLEAVE);
        for (int j = start; j < last; j += INTERLEAVE * INTERLEAVE) {
            Emitter e = emitters[j];
            if (e.position.w <= 0.0) continue;
#ifdef ROOMS
            if (!lights_room(e.position, room)) continue;
#endif
            vec3 d = p - e.position.xyz;
            float facing = -dot(n, d) * inversesqrt(max(dot(d, d), 1e-30));
            if (facing <= 0.0) continue;
            vec3 light = shared_emitter_light(e, d, singularity_bound, held_bound) * facing;
            if (max(light.r, max(light.g, light.b)) <= 0.0) continue;
            if (levels_blocked(e.position.xyz + EMITTER_OFFSET * level_voxels[0] * e.normal.xyz, from_pixel, e.position.xyz))
                continue;
            sum += light;
        }
        sum *= float(INTERLEAVE * INTERLEAVE);
    }
    vec4 before = accumulate ? imageLoad(gathered, pixel) : vec4(0.0);
    imageStore(gathered, pixel, before + vec4(sum, 0.0));
}
