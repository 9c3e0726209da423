// The scene's surfaces voxelised (voxelise_small.comp, occupancy.frag): a voxel is non-zero
// where a surface passes, and a cell (per_cell voxels a side) of the coarse occupancy where
// any of its voxels is. Each grid's voxels follow the one before's along z (`layer`).
// Points are in voxel units of their grid (voxel (i, j, k) spans [i, i+1] x ...).
#include "segment.glsl"
const float MARCH_STEP = 0.7;  // voxels between samples: a surface one voxel thick is not stepped over

// Whether the part [t_from, t_to] of the segment a -> b (in `layer`'s voxel units) crosses a
// surface, with segment_blocked's exceptions. Empty cells are crossed in one step.
bool part_blocked(usampler3D occupancy, usampler3D coarse, int per_cell, int layer, vec3 a, vec3 b, float t_from,
                  float t_to, vec3 surface, float radius, bool skip_end) {
    vec3 d = b - a;
    int cells = textureSize(coarse, 0).x;
    ivec3 voxel_layer = ivec3(0, 0, layer * cells * per_cell), cell_layer = ivec3(0, 0, layer * cells);
    vec3 inverse = 1.0 / (d + vec3(1e-30));
    float step = MARCH_STEP / max(length(d), 1e-30);
    float t = t_from > 0.0 ? t_from + 1e-3 * step : t_from + step;  // a part that starts at a level's side samples it
    ivec3 end = ivec3(floor(b));
    while (t < t_to) {
        vec3 x = a + d * t;
        ivec3 cell = ivec3(floor(x / float(per_cell)));
        if (texelFetch(coarse, cell + cell_layer, 0).r == 0u) {
            vec3 low = vec3(cell * per_cell), high = low + float(per_cell);
            vec3 exits = (mix(low, high, greaterThan(d, vec3(0.0))) - a) * inverse;
            t = max(t + step, min(exits.x, min(exits.y, exits.z)) + 1e-4 * step);
            continue;
        }
        ivec3 v = ivec3(floor(x));
        if ((v != end || !skip_end) && distance(x, surface) >= radius && texelFetch(occupancy, v + voxel_layer, 0).r != 0u)
            return true;
        t += step;
    }
    return false;
}

// Whether the segment a -> b crosses a surface, not counting samples within `radius` of
// `surface` (the surface the segment leaves, and where it bends away from it at an edge),
// anything outside the grid, and with `skip_end` the voxel b lies in (a cell centre on a
// surface still gathers light; a lookup does not use it).
bool segment_blocked(usampler3D occupancy, usampler3D coarse, int per_cell, int layer, vec3 a, vec3 b,
                     vec3 surface, float radius, bool skip_end) {
    vec2 inside = part_inside(a, b, float(textureSize(coarse, 0).x * per_cell));
    return inside.x < inside.y && part_blocked(occupancy, coarse, per_cell, layer, a, b, inside.x, inside.y, surface,
                                               radius, skip_end);
}
