#version 450 core
// Voxelisation: the scene drawn orthographically (occupancy.geom picks each triangle's axis)
// onto a square the size of the occupancy grid; every fragment marks the voxel its surface
// point lies in.
in vec3 voxel_position;
layout(r8ui, binding = 0) uniform writeonly uimage3D occupancy;
uniform vec3 grid_origin;
uniform float voxel_size;
layout(location = 0) out vec4 unused;

void main() {
    ivec3 v = ivec3(floor((voxel_position - grid_origin) / voxel_size));
    if (all(greaterThanEqual(v, ivec3(0))) && all(lessThan(v, imageSize(occupancy)))) imageStore(occupancy, v, uvec4(1u));
    unused = vec4(0.0);
}
