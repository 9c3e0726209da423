#version 450 core
// Voxelisation of the large triangles (voxelise_small.comp lists them): drawn
// orthographically (occupancy.geom picks each triangle's axis) onto a square the size of
// one grid's occupancy; every fragment marks the voxel its surface point lies in, and the
// cell that voxel lies in, in grid `layer`'s part of the volumes.
#include "occupancy_mark.glsl"
in vec3 voxel_position;
uniform int layer;
uniform vec3 grid_origin;
uniform float voxel_size;

void main() {
    mark_voxel(layer, ivec3(floor((voxel_position - grid_origin) / voxel_size)));
}
