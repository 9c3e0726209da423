// Visibility through nested grid levels (gpu/occupancy.py): each part of a segment is
// marched in the finest level that holds it. LEVELS levels, finest first; `level_layers`
// says which layer of the occupancy holds each.
#include "occupancy.glsl"
#include "occupancy_volumes.glsl"
uniform vec3 level_origins[LEVELS];
uniform float level_voxels[LEVELS];  // a voxel's side in each level
uniform int level_layers[LEVELS];
uniform int voxels;                  // a level's voxels along each side
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
        int layer = level_layers[level];
        vec2 inside = part_inside(la, lb, float(voxels));
        if (inside.x >= inside.y) continue;
        if (finer.x >= finer.y) {
            if (part_blocked(occupancy, coarse, voxels_per_cell, layer, la, lb, inside.x, inside.y, le, radius, true))
                return true;
        } else {
            if (inside.x < finer.x && part_blocked(occupancy, coarse, voxels_per_cell, layer, la, lb, inside.x, finer.x,
                                                   le, radius, true)) return true;
            if (finer.y < inside.y && part_blocked(occupancy, coarse, voxels_per_cell, layer, la, lb, finer.y, inside.y,
                                                   le, radius, true)) return true;
        }
        finer = inside;
    }
    return false;
}
