#version 450 core
// Dual paraboloid rasterisation (thesis eq. 3) per vertex, for triangles wholly in front
// of the rim (rim_split.comp sorts them out; the ones crossing it go through dpm.geom).
// With w = 1 the rasterizer interpolates linearly between projected vertices, like
// dpm.geom's output: that is the distortion WDPM corrects. The fragment reads its surface
// by the triangle's number and weights (surface_vertices.glsl).
#include "paraboloid.glsl"
in vec3 in_position;
uniform mat4 hemisphere_view;  // world to hemisphere space (+z the hemisphere's axis)
uniform float near;
uniform float far;
out vec2 surface_weights;
flat out int surface_triangle;

void main() {
    vec3 p = (hemisphere_view * vec4(in_position, 1.0)).xyz;
    gl_Position = paraboloid_clip_position(p, near, far);
    int corner = gl_VertexID % 3;  // drawn through rim_split's lists: the index is the vertex's number
    surface_weights = vec2(corner == 1, corner == 2);
    surface_triangle = gl_VertexID / 3;
}
