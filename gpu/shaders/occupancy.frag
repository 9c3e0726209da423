#version 450 core
// Voxelisation of the large triangles (voxelise_small.comp lists them): drawn
// orthographically (occupancy.geom picks each triangle's axis) onto a square the size of
// one grid's occupancy; every fragment marks the voxel its surface point lies in, and the
// cell that voxel lies in, in grid `layer`'s part of the volumes.
in vec3 voxel_position;
layout(r8ui, binding = 0) uniform writeonly uimage3D occupancy;
layout(r8ui, binding = 1) uniform writeonly uimage3D coarse;  // one texel per cell
uniform int voxels_per_cell;
uniform int voxels;  // a grid's voxels along each side
uniform int layer;
uniform vec3 grid_origin;
uniform float voxel_size;
layout(location = 0) out vec4 unused;

void main() {
    ivec3 v = ivec3(floor((voxel_position - grid_origin) / voxel_size));
    if (all(greaterThanEqual(v, ivec3(0))) && all(lessThan(v, ivec3(voxels)))) {
        imageStore(occupancy, v + ivec3(0, 0, layer * voxels), uvec4(1u));
        imageStore(coarse, v / voxels_per_cell + ivec3(0, 0, layer * (voxels / voxels_per_cell)), uvec4(1u));
    }
    unused = vec4(0.0);
}
