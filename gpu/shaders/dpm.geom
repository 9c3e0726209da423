#version 450 core
// Dual paraboloid rasterisation: clip each triangle at the hemisphere's rim in hemisphere
// space (exactly, before projecting), then project each vertex with eq. 3. The rasterizer
// interpolates linearly between projected vertices: that is the distortion WDPM corrects.
#include "paraboloid.glsl"
layout(triangles) in;
layout(triangle_strip, max_vertices = 4) out;
in vec3 world_position_v[];
in vec3 world_normal_v[];
in vec4 surface_albedo_v[];
in vec4 surface_coord_v[];
in vec4 surface_transmission_v[];
in vec4 surface_specular_v[];
in float surface_metallic_v[];
out vec3 world_position;
out vec3 world_normal;
out vec4 surface_albedo;
out vec4 surface_coord;
out vec4 surface_transmission;
out vec4 surface_specular;
out float surface_metallic;
uniform mat4 hemisphere_view;  // world to hemisphere space (+z the hemisphere's axis)
uniform float near;
uniform float far;

vec3 kept_position[4];
vec3 kept_normal[4];
vec4 kept_albedo[4];
vec4 kept_coord[4];
vec4 kept_transmission[4];
vec4 kept_specular[4];
float kept_metallic[4];
int kept = 0;

void keep(vec3 p, vec3 n, vec4 a, vec4 c, vec4 t, vec4 s, float m) {
    kept_position[kept] = p;
    kept_normal[kept] = n;
    kept_albedo[kept] = a;
    kept_coord[kept] = c;
    kept_transmission[kept] = t;
    kept_specular[kept] = s;
    kept_metallic[kept] = m;
    kept += 1;
}

void emit(int i) {
    gl_Position = paraboloid_clip_position((hemisphere_view * vec4(kept_position[i], 1.0)).xyz, near, far);
    world_position = kept_position[i];
    world_normal = kept_normal[i];
    surface_albedo = kept_albedo[i];
    surface_coord = kept_coord[i];
    surface_transmission = kept_transmission[i];
    surface_specular = kept_specular[i];
    surface_metallic = kept_metallic[i];
    EmitVertex();
}

void main() {
    float z[3];
    for (int i = 0; i < 3; ++i) z[i] = (hemisphere_view * vec4(world_position_v[i], 1.0)).z;
    // Sutherland-Hodgman against z >= 0: at most four vertices survive.
    for (int i = 0; i < 3; ++i) {
        int j = (i + 1) % 3;
        if (z[i] >= 0.0) keep(world_position_v[i], world_normal_v[i], surface_albedo_v[i], surface_coord_v[i], surface_transmission_v[i],
                            surface_specular_v[i], surface_metallic_v[i]);
        if ((z[i] >= 0.0) != (z[j] >= 0.0)) {
            float f = z[i] / (z[i] - z[j]);
            keep(mix(world_position_v[i], world_position_v[j], f), mix(world_normal_v[i], world_normal_v[j], f),
                 mix(surface_albedo_v[i], surface_albedo_v[j], f), mix(surface_coord_v[i], surface_coord_v[j], f),
                 mix(surface_transmission_v[i], surface_transmission_v[j], f),
                 mix(surface_specular_v[i], surface_specular_v[j], f),
                 mix(surface_metallic_v[i], surface_metallic_v[j], f));
        }
    }
    if (kept < 3) return;
    emit(0);
    emit(1);
    if (kept == 4) emit(3);
    emit(2);
    EndPrimitive();
}
