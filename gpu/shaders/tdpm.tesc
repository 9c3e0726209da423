#version 450 core
// TDPM tessellation factors (thesis eq. 8-9): project the patch's vertices with eq. 3;
// an edge gets ceil(projected length / u) segments, the inside 2 round(max height / u).
#include "paraboloid.glsl"
layout(vertices = 3) out;
in vec3 world_position_v[];
in vec2 surface_weights_v[];
in int surface_triangle_v[];
out vec3 world_position_c[];
out vec2 surface_weights_c[];
patch out int surface_triangle_c;
uniform mat4 hemisphere_view;
uniform float tessellation_unit;
const float MAX_LEVEL = 64.0;  // GL's guaranteed GL_MAX_TESS_GEN_LEVEL

void main() {
    world_position_c[gl_InvocationID] = world_position_v[gl_InvocationID];
    surface_weights_c[gl_InvocationID] = surface_weights_v[gl_InvocationID];
    if (gl_InvocationID != 0) return;
    surface_triangle_c = surface_triangle_v[0];
    vec3 h[3];
    vec2 p[3];
    for (int i = 0; i < 3; ++i) {
        h[i] = (hemisphere_view * vec4(world_position_v[i], 1.0)).xyz;
        p[i] = paraboloid_project(h[i]);
    }
    if (h[0].z < 0.0 && h[1].z < 0.0 && h[2].z < 0.0) {  // wholly behind: discard the patch
        gl_TessLevelOuter[0] = gl_TessLevelOuter[1] = gl_TessLevelOuter[2] = 0.0;
        gl_TessLevelInner[0] = 0.0;
        return;
    }
    // Outer level i belongs to the edge opposite vertex i.
    float edge[3] = float[3](length(p[1] - p[2]), length(p[2] - p[0]), length(p[0] - p[1]));
    vec2 a = p[1] - p[0], b = p[2] - p[0];
    float doubled_area = abs(a.x * b.y - a.y * b.x);
    float height = 0.0;
    for (int i = 0; i < 3; ++i) {
        gl_TessLevelOuter[i] = clamp(ceil(edge[i] / tessellation_unit), 1.0, MAX_LEVEL);
        height = max(height, doubled_area / max(edge[i], 1e-12));
    }
    gl_TessLevelInner[0] = clamp(2.0 * round(height / tessellation_unit), 1.0, MAX_LEVEL);
}
