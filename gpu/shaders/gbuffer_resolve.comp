#version 450 core
// Camera G-buffer, second half: at each pixel gbuffer.frag drew, the surface of the
// triangle it saw, where the pixel's ray meets it, read from the vertex buffer
// (triangle_corners.glsl): the normal turned toward the camera (surfaces are two-sided)
// and the albedo (with SURFACE_IMAGES times the image's colour gbuffer.frag sampled)
// darkened by the glossy layer over it toward the camera (specular.glsl), packed into one
// texel (gbuffer.glsl), and the glossy reflection (F0, roughness, metallic) in a second.
// With SHUT_SIDES the side of a solid's face that looks into it (gpu/closed_meshes.py: no
// light reaches it) is black: a camera inside a solid sees what Cycles shows there.
#include "gbuffer.glsl"
#include "common.glsl"
#include "specular.glsl"
#include "triangle_corners.glsl"
#include "face_codes.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
#ifdef SHUT_SIDES
layout(std430, binding = 0) readonly buffer OpenSides { uint open_sides[]; };  // a byte a triangle
#endif
layout(rgba32ui, binding = 0) uniform writeonly uimage2D g_surface_image;
layout(rgba16ui, binding = 1) uniform writeonly uimage2D g_specular_image;
uniform usampler2D g_triangles;  // gbuffer.frag's
#ifdef SURFACE_IMAGES
uniform sampler2D g_image_colours;
#endif

// The barycentric weights of the triangle's second and third corners where the ray
// through the centre of `pixel` meets its plane (Moller-Trumbore).
vec2 weights_at(ivec2 pixel, int triangle) {
    vec3 p0 = vertex_position(3 * triangle);
    vec3 e1 = vertex_position(3 * triangle + 1) - p0, e2 = vertex_position(3 * triangle + 2) - p0;
    vec3 origin = gbuffer_unproject(pixel, 0.0);
    vec3 direction = gbuffer_unproject(pixel, 1.0) - origin;
    vec3 p = cross(direction, e2);
    float det = dot(e1, p);
    if (abs(det) < 1e-30) return vec2(1.0 / 3.0);
    vec3 t = origin - p0;
    return vec2(dot(t, p), dot(direction, cross(t, e1))) / det;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(g_surface_image)))) return;
    if (texelFetch(g_depth, pixel, 0).r >= 1.0) return;
    uint seen = texelFetch(g_triangles, pixel, 0).r;
    int triangle = seen_triangle(seen);
    vec2 w = weights_at(pixel, triangle);
    vec3 n = normalize(corner_mix3(triangle, w, VERTEX_NORMAL));
#ifdef SHUT_SIDES
    if ((TRIANGLE_BYTE(open_sides, triangle) & (seen_front(seen) ? 1u : 2u)) == 0u) {  // FRONT: the side its winding faces
        imageStore(g_surface_image, pixel, gbuffer_pack(n, vec3(0.0)));
        imageStore(g_specular_image, pixel, gbuffer_pack_specular(vec3(0.0), 1.0, 0.0));
        return;
    }
#endif
    vec3 v = gbuffer_view(pixel, corner_mix3(triangle, w, 0));
    if (dot(n, v) < 0.0) n = -n;
    vec3 albedo = corner_mix3(triangle, w, VERTEX_ALBEDO);
#ifdef SURFACE_IMAGES
    albedo *= texelFetch(g_image_colours, pixel, 0).rgb;
#endif
    vec4 specular = corner_mix4(triangle, w, VERTEX_SPECULAR);
    float metallic = corner_mix(triangle, w, VERTEX_METALLIC);
    float kept = diffuse_under_layer(specular.rgb, metallic, specular.a, max(dot(n, v), 1e-4));
    imageStore(g_surface_image, pixel, gbuffer_pack(n, albedo * kept));
    imageStore(g_specular_image, pixel, gbuffer_pack_specular(specular.rgb, specular.a, metallic));
}
