#version 450 core
// The scene's arrays, uploaded as it holds them, interleaved into the vertex buffer
// (gpu/mesh_buffer.py VERTEX_LAYOUT) on the GPU: one invocation per triangle writes its
// three vertices. `Positions` and `Normals` hold the corners' (9 floats a triangle each;
// the raster passes keep drawing from the positions); `Surfaces` the surface arrays one after another, each at its offset in
// floats (-1: the scene has none; its default then): albedo (3 a triangle), corner colours
// (9), alpha (1), transmission (4: tint, share), corner UVs (6), image and alpha-image
// layers (2), glossy layer (5: F0 rgb, roughness, metallic).
#include "vertex_layout.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Surfaces { float surfaces[]; };
layout(std430, binding = 2) writeonly buffer Vertices { float vertices[]; };
layout(std430, binding = 3) readonly buffer Normals { float normals[]; };
uniform int triangle_count;
uniform int first_triangle;  // this dispatch's first (a dispatch reaches 65,535 workgroups)
uniform int albedo_at;
uniform int colours_at;
uniform int alpha_at;
uniform int transmission_at;
uniform int uvs_at;
uniform int layers_at;
uniform int specular_at;

float surface(int at, int t, int width, int i, float missing) {
    return at < 0 ? missing : surfaces[at + t * width + i];
}

void main() {
    int t = first_triangle + int(gl_GlobalInvocationID.x);
    if (t >= triangle_count) return;
    vec3 albedo = vec3(surface(albedo_at, t, 3, 0, 0.0), surface(albedo_at, t, 3, 1, 0.0), surface(albedo_at, t, 3, 2, 0.0));
    vec4 transmission = vec4(surface(transmission_at, t, 4, 0, 1.0), surface(transmission_at, t, 4, 1, 1.0),
                             surface(transmission_at, t, 4, 2, 1.0), surface(transmission_at, t, 4, 3, 0.0));
    float opaque = transmission_at < 0 ? 1.0 : max(1.0 - transmission.w, 1e-6);
    float alpha = surface(alpha_at, t, 1, 0, 1.0);
    vec4 specular = vec4(surface(specular_at, t, 5, 0, 0.0), surface(specular_at, t, 5, 1, 0.0),
                         surface(specular_at, t, 5, 2, 0.0), surface(specular_at, t, 5, 3, 1.0));
    float metallic = surface(specular_at, t, 5, 4, 0.0);
    for (int corner = 0; corner < 3; ++corner) {
        int at = (3 * t + corner) * VERTEX_FLOATS;
        for (int i = 0; i < 3; ++i) {
            vertices[at + i] = positions[9 * t + 3 * corner + i];
            vertices[at + VERTEX_NORMAL + i] = normals[9 * t + 3 * corner + i];
        }
        // the triangle's albedo times the corner's colour, divided where the surface
        // transmits by what does not (the opaque part's albedo, surface.glsl)
        vec3 colour = albedo;
        for (int i = 0; i < 3; ++i) colour[i] *= surface(colours_at, t, 9, 3 * corner + i, 1.0);
        if (transmission_at >= 0) colour = clamp(colour / opaque, 0.0, 1.0);
        for (int i = 0; i < 3; ++i) vertices[at + VERTEX_ALBEDO + i] = colour[i];
        vertices[at + VERTEX_ALPHA] = alpha;
        vertices[at + VERTEX_SURFACE] = surface(uvs_at, t, 6, 2 * corner, 0.0);
        vertices[at + VERTEX_SURFACE + 1] = surface(uvs_at, t, 6, 2 * corner + 1, 0.0);
        vertices[at + VERTEX_SURFACE + 2] = surface(layers_at, t, 2, 0, -1.0);
        vertices[at + VERTEX_ALPHA_LAYER] = surface(layers_at, t, 2, 1, -1.0);
        for (int i = 0; i < 4; ++i) vertices[at + VERTEX_TINT + i] = transmission[i];
        for (int i = 0; i < 4; ++i) vertices[at + VERTEX_SPECULAR + i] = specular[i];
        vertices[at + VERTEX_METALLIC] = metallic;
    }
}
