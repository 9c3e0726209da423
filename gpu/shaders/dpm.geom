#version 450 core
// Dual paraboloid rasterisation: clip each triangle at the hemisphere's rim in hemisphere
// space (exactly, before projecting), then project each vertex with eq. 3. The rasterizer
// interpolates linearly between projected vertices: that is the distortion WDPM corrects.
#include "paraboloid.glsl"
layout(triangles) in;
layout(triangle_strip, max_vertices = 4) out;
in vec3 world_position_v[];
in vec2 surface_weights_v[];
in int surface_triangle_v[];
out vec2 surface_weights;
flat out int surface_triangle;
uniform mat4 hemisphere_view;  // world to hemisphere space (+z the hemisphere's axis)
uniform float near;
uniform float far;

vec3 kept_position[4];
vec2 kept_weights[4];
int kept = 0;

void keep(vec3 p, vec2 w) {
    kept_position[kept] = p;
    kept_weights[kept] = w;
    kept += 1;
}

void emit(int i) {
    gl_Position = paraboloid_clip_position((hemisphere_view * vec4(kept_position[i], 1.0)).xyz, near, far);
    surface_weights = kept_weights[i];
    surface_triangle = surface_triangle_v[0];
    EmitVertex();
}

void main() {
    float z[3];
    for (int i = 0; i < 3; ++i) z[i] = (hemisphere_view * vec4(world_position_v[i], 1.0)).z;
    // Sutherland-Hodgman against z >= 0: at most four vertices survive.
    for (int i = 0; i < 3; ++i) {
        int j = (i + 1) % 3;
        if (z[i] >= 0.0) keep(world_position_v[i], surface_weights_v[i]);
        if ((z[i] >= 0.0) != (z[j] >= 0.0)) {
            float f = z[i] / (z[i] - z[j]);
            keep(mix(world_position_v[i], world_position_v[j], f), mix(surface_weights_v[i], surface_weights_v[j], f));
        }
    }
    if (kept < 3) return;
    emit(0);
    emit(1);
    if (kept == 4) emit(3);
    emit(2);
    EndPrimitive();
}
