// Visibility through nested grid levels (gpu/occupancy.py): each part of a segment is
// marched in the finest level that holds it. MARCH_LEVELS levels, finest first, the last
// the occupancy's outer grid; `level_layers` says which layer of the occupancy holds each.
#include "occupancy.glsl"
#include "occupancy_volumes.glsl"
uniform vec3 level_origins[MARCH_LEVELS];
uniform float level_voxels[MARCH_LEVELS];  // a voxel's side in each level
uniform int level_layers[MARCH_LEVELS];
uniform int voxels;                  // a level's voxels along each side
uniform int first_level;             // the finest level marched (0 unless set): finer ones are left to it
const float EMITTER_RADIUS = 0.5;  // voxels of the first level marched around a VPL where the march sees no occluder (its own surface)
const float COARSE_EMITTER_RADIUS = 1.5;  // a coarser level's voxels around it where its own surface, thicker there, is not seen
const float EMITTER_OFFSET = 1.0;  // finest voxels off a VPL's surface where its marches start: out of its own voxel

// Whether the segment a -> b (world units) crosses a surface: each part of it in the finest
// level that holds that part, marched in that level's voxels.
bool levels_blocked(vec3 a, vec3 b, vec3 emitter) {
    vec2 finer = vec2(1.0, 0.0);  // the part inside the finer levels, empty before the finest
    for (int level = first_level; level < MARCH_LEVELS; ++level) {
        vec3 origin = level_origins[level];
        float size = level_voxels[level];
        vec3 la = (a - origin) / size, lb = (b - origin) / size, le = (emitter - origin) / size;
        bool coarser = level > first_level && level < MARCH_LEVELS - 1;  // not the outer grid: walls it holds stand
        float radius = max(EMITTER_RADIUS * level_voxels[first_level] / size, coarser ? COARSE_EMITTER_RADIUS : 0.0);
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
