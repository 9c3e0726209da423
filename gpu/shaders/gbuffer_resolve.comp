#version 450 core
// Camera G-buffer, second half: at each pixel gbuffer.frag drew, the surface of the
// triangle it saw, where the pixel's ray meets it, read from the vertex buffer
// (vertex_layout.glsl): the normal turned toward the camera (surfaces are two-sided) and
// the albedo (with SURFACE_IMAGES times the image's colour gbuffer.frag sampled) darkened by the glossy layer
// over it toward the camera (specular.glsl), packed into one texel (gbuffer.glsl), and
// the glossy reflection (F0, roughness, metallic) in a second.
// With SHUT_SIDES the side of a solid's face that looks into it (gpu/closed_meshes.py: no
// light reaches it) is black: a camera inside a solid sees what Cycles shows there.
#include "gbuffer.glsl"
#include "common.glsl"
#include "specular.glsl"
#include "vertex_layout.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 5) readonly buffer SurfaceVertices { float vertices[]; };
#ifdef SHUT_SIDES
layout(std430, binding = 0) readonly buffer OpenSides { uint open_sides[]; };  // a byte a triangle
#endif
layout(rgba32ui, binding = 0) uniform writeonly uimage2D g_surface_image;
layout(rgba16ui, binding = 1) uniform writeonly uimage2D g_specular_image;
uniform usampler2D g_triangles;  // gbuffer.frag's
#ifdef SURFACE_IMAGES
uniform sampler2D g_image_colours;
#endif
uniform vec4 camera_eye;  // the camera's position, w 1; orthographic: the direction toward it, w 0

int first_vertex;  // the triangle's first vertex's first float

float vertex_float(int corner, int offset) {
    return vertices[first_vertex + corner * VERTEX_FLOATS + offset];
}

vec3 corner_position(int corner) {
    return vec3(vertex_float(corner, 0), vertex_float(corner, 1), vertex_float(corner, 2));
}

// The barycentric weights of the triangle's second and third corners where the ray
// through the window point `at` (in pixels) meets its plane (Moller-Trumbore).
vec2 weights_at(vec2 at, vec3 p0, vec3 e1, vec3 e2) {
    vec2 ndc = at / vec2(imageSize(g_surface_image)) * 2.0 - 1.0;
    vec4 near = inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far = inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 origin = near.xyz / near.w;
    vec3 direction = far.xyz / far.w - origin;
    vec3 p = cross(direction, e2);
    float det = dot(e1, p);
    if (abs(det) < 1e-30) return vec2(1.0 / 3.0);
    vec3 t = origin - p0;
    return vec2(dot(t, p), dot(direction, cross(t, e1))) / det;
}

float interpolated(vec2 w, int offset) {
    return (1.0 - w.x - w.y) * vertex_float(0, offset) + w.x * vertex_float(1, offset) + w.y * vertex_float(2, offset);
}

vec4 interpolated4(vec2 w, int offset) {
    return vec4(interpolated(w, offset), interpolated(w, offset + 1), interpolated(w, offset + 2),
                interpolated(w, offset + 3));
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(g_surface_image)))) return;
    if (texelFetch(g_depth, pixel, 0).r >= 1.0) return;
    uint seen = texelFetch(g_triangles, pixel, 0).r;
    int triangle = int(seen & 0x7fffffffu);
    first_vertex = 3 * VERTEX_FLOATS * triangle;
    vec3 p0 = corner_position(0);
    vec3 e1 = corner_position(1) - p0, e2 = corner_position(2) - p0;
    vec2 w = weights_at(vec2(pixel) + 0.5, p0, e1, e2);
    vec3 n = normalize(interpolated4(w, VERTEX_NORMAL).xyz);
#ifdef SHUT_SIDES
    uint sides = open_sides[triangle >> 2] >> (8 * (triangle & 3));
    if ((sides & ((seen >> 31) == 1u ? 1u : 2u)) == 0u) {  // FRONT: the side its winding faces
        imageStore(g_surface_image, pixel, gbuffer_pack(n, vec3(0.0)));
        imageStore(g_specular_image, pixel, gbuffer_pack_specular(vec3(0.0), 1.0, 0.0));
        return;
    }
#endif
    vec3 position = p0 + w.x * e1 + w.y * e2;
    vec3 v = normalize(camera_eye.xyz - position * camera_eye.w);
    if (dot(n, v) < 0.0) n = -n;
    vec3 albedo = interpolated4(w, VERTEX_ALBEDO).rgb;
#ifdef SURFACE_IMAGES
    albedo *= texelFetch(g_image_colours, pixel, 0).rgb;
#endif
    vec4 specular = interpolated4(w, VERTEX_SPECULAR);
    float metallic = interpolated(w, VERTEX_METALLIC);
    float kept = diffuse_under_layer(specular.rgb, metallic, specular.a, max(dot(n, v), 1e-4));
    imageStore(g_surface_image, pixel, gbuffer_pack(n, albedo * kept));
    imageStore(g_specular_image, pixel, gbuffer_pack_specular(specular.rgb, specular.a, metallic));
}
