#version 450 core
// VPL gathering (gpu/vpl_gather.py): every pixel of the camera's G-buffer sums the
// irradiance of the VPLs that see it, through a march in the occupancy of every grid level. Interleaved: the
// pixel at (x, y) of each INTERLEAVE x INTERLEAVE block takes every INTERLEAVE²-th VPL
// from its own offset, its sum scaled by INTERLEAVE² (vpl_gather_filter.comp puts the
// block's subsets back together). One dispatch adds the VPLs [first, first + batch) of
// one set to what the ones before left: llvmpipe ends a loop nest after 65,535 iterations.
#include "common.glsl"
#include "gbuffer.glsl"
#include "emitter.glsl"
#include "occupancy.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(rgba32f, binding = 0) uniform image2D gathered;
uniform usampler3D occupancy;
uniform usampler3D coarse;
uniform vec3 level_origins[LEVELS];
uniform float level_voxels[LEVELS];  // a voxel's side in each level
uniform int voxels;                  // a level's voxels along each side
uniform int voxels_per_cell;
uniform int emitter_count;
uniform int first_emitter;
uniform int batch;
uniform bool accumulate;
const float OFF_SURFACE = 1.5;     // finest voxels off the pixel's surface where its marches end
const float EMITTER_RADIUS = 0.5;  // finest voxels around a VPL where the march sees no occluder (its own surface)
const float EMITTER_OFFSET = 1.0;  // finest voxels off a VPL's surface where its marches start: out of its own voxel

// Whether the segment a -> b (world units) crosses a surface: each part of it in the finest
// level that holds that part, marched in that level's voxels.
bool levels_blocked(vec3 a, vec3 b, vec3 emitter) {
    vec2 finer = vec2(1.0, 0.0);  // the part inside the finer levels, empty before the finest
    for (int level = 0; level < LEVELS; ++level) {
        vec3 origin = level_origins[level];
        float size = level_voxels[level];
        vec3 la = (a - origin) / size, lb = (b - origin) / size, le = (emitter - origin) / size;
        float radius = EMITTER_RADIUS * level_voxels[0] / size;
        vec2 inside = part_inside(la, lb, float(voxels));
        if (inside.x >= inside.y) continue;
        if (finer.x >= finer.y) {
            if (part_blocked(occupancy, coarse, voxels_per_cell, level, la, lb, inside.x, inside.y, le, radius, true))
                return true;
        } else {
            if (inside.x < finer.x && part_blocked(occupancy, coarse, voxels_per_cell, level, la, lb, inside.x, finer.x,
                                                   le, radius, true)) return true;
            if (finer.y < inside.y && part_blocked(occupancy, coarse, voxels_per_cell, level, la, lb, finer.y, inside.y,
                                                   le, radius, true)) return true;
        }
        finer = inside;
    }
    return false;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(gathered)))) return;
    vec3 p, n, albedo;
    vec3 sum = vec3(0.0);
    if (gbuffer_surface(pixel, p, n, albedo)) {
        int subset = (pixel.y % INTERLEAVE) * INTERLEAVE + pixel.x % INTERLEAVE;
        vec3 from_pixel = p + OFF_SURFACE * level_voxels[0] * n;
        int last = min(first_emitter + batch, emitter_count);
        int start = first_emitter + (subset - first_emitter % (INTERLEAVE * INTERLEAVE) + INTERLEAVE * INTERLEAVE)
                    % (INTERLEAVE * INTERLEAVE);
        for (int j = start; j < last; j += INTERLEAVE * INTERLEAVE) {
            Emitter e = emitters[j];
            if (e.position.w <= 0.0) continue;
            vec3 d = p - e.position.xyz;
            float facing = -dot(n, d) * inversesqrt(max(dot(d, d), 1e-30));
            if (facing <= 0.0) continue;
            vec3 light = emitter_light(e, d) * facing;
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
