#version 450 core
// Voxelisation's one draw: each triangle goes to the projection along the axis its normal is
// closest to, where it covers the most fragments (occupancy.frag marks their voxels).
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 world_position[];
out vec3 voxel_position;
uniform mat4 axis_projections[3];  // along x, y, z

void main() {
    vec3 n = abs(cross(world_position[1] - world_position[0], world_position[2] - world_position[0]));
    int axis = n.x >= n.y && n.x >= n.z ? 0 : (n.y >= n.z ? 1 : 2);
    for (int i = 0; i < 3; ++i) {
        voxel_position = world_position[i];
        gl_Position = axis_projections[axis] * vec4(world_position[i], 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
