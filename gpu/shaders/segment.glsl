// The part of the segment a -> b (in a grid's voxel units) inside a grid of `voxels` a side,
// as [enter, leave] along it (empty when enter >= leave).
vec2 part_inside(vec3 a, vec3 b, float voxels) {
    vec3 inverse = 1.0 / (b - a + vec3(1e-30));
    vec3 t0 = -a * inverse, t1 = (vec3(voxels) - a) * inverse;
    vec3 near = min(t0, t1), far = max(t0, t1);
    return vec2(max(0.0, max(near.x, max(near.y, near.z))), min(1.0, min(far.x, min(far.y, far.z))));
}
