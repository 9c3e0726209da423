// The scene's surfaces voxelised (occupancy.frag): a voxel is non-zero where a surface
// passes. Points are in voxel units (voxel (i, j, k) spans [i, i+1] x ...).
const float MARCH_STEP = 0.7;  // voxels between samples: a surface one voxel thick is not stepped over

// Whether the segment a -> b crosses a surface, not counting the voxel b lies in, samples
// within `radius` of `surface` (the surface the segment leaves, and where it bends away
// from it at an edge) or anything outside the grid.
bool segment_blocked(usampler3D occupancy, vec3 a, vec3 b, vec3 surface, float radius) {
    vec3 d = b - a;
    ivec3 size = textureSize(occupancy, 0);
    // The part of the segment inside the grid (slabs), marched from end to end.
    vec3 inverse = 1.0 / (d + vec3(1e-30));
    vec3 t0 = (vec3(0.0) - a) * inverse, t1 = (vec3(size) - a) * inverse;
    vec3 near = min(t0, t1), far = max(t0, t1);
    float enter = max(0.0, max(near.x, max(near.y, near.z)));
    float leave = min(1.0, min(far.x, min(far.y, far.z)));
    if (enter >= leave) return false;
    int steps = int(ceil(length(d) * (leave - enter) / MARCH_STEP));
    ivec3 end = ivec3(floor(b));
    for (int i = 1; i < steps; ++i) {
        vec3 x = a + d * mix(enter, leave, float(i) / float(steps));
        ivec3 v = ivec3(floor(x));
        if (v == end || distance(x, surface) < radius) continue;
        if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, size))) continue;
        if (texelFetch(occupancy, v, 0).r != 0u) return true;
    }
    return false;
}
