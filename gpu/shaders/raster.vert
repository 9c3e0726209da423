#version 450 core
// Scene triangles for every raster pass (RSM faces, the camera's G-buffer, voxelisation):
// the fragment reads its surface from the vertex buffer (surface_vertices.glsl) by the
// triangle's number and the two weights interpolated here.
in vec3 in_position;
uniform mat4 view_projection;
out vec3 world_position;  // for the voxelisation's geometry shader
out vec2 surface_weights;
flat out int surface_triangle;  // the triangle's number in the vertex buffer (a culled draw's
                                 // gl_PrimitiveID restarts at each cluster)

void main() {
    int corner = gl_VertexID % 3;
    world_position = in_position;
    surface_weights = vec2(corner == 1, corner == 2);
    surface_triangle = gl_VertexID / 3;
    gl_Position = view_projection * vec4(in_position, 1.0);
}
