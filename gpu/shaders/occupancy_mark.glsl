// Writing the occupancy (gpu/occupancy.py): every grid's voxels and cells, one grid after the
// other along z.
layout(r8ui, binding = 0) uniform writeonly uimage3D occupancy;
layout(r8ui, binding = 1) uniform writeonly uimage3D coarse;  // one texel per cell
uniform int voxels;  // a grid's voxels along each side
uniform int voxels_per_cell;

// Mark voxel v of grid `layer`, and its cell; nothing outside the grid.
void mark_voxel(int layer, ivec3 v) {
    if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, ivec3(voxels)))) return;
    imageStore(occupancy, v + ivec3(0, 0, layer * voxels), uvec4(1u));
    imageStore(coarse, v / voxels_per_cell + ivec3(0, 0, layer * (voxels / voxels_per_cell)), uvec4(1u));
}
