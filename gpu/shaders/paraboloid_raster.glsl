// A paraboloid face's triangles rasterised by a compute pass (rim_split.comp with RASTER)
// as the rasterizer draws dpm.vert's, and the texels it keeps: per atlas texel the
// nearest depth and the first triangle there, each stored inverted (0: none) so that an
// atomic maximum keeps the least and a zeroed buffer is empty. Included after the pass
// declares `face_origin` (the face's lower-left texel in the atlas) and `resolution`
// (texels along one side of a face).
#include "paraboloid.glsl"
uniform int atlas_width;  // texels along a row of the atlas
uniform float near;
uniform float far;

// The atlas position (x, y in texels) and depth (z, in [0, 1]) where the rasterizer puts
// hemisphere-space point p of this face: dpm.vert's clip position in the face's viewport.
vec3 paraboloid_window(vec3 p) {
    vec4 clip = paraboloid_clip_position(p, near, far);
    return vec3(face_origin + (clip.xy * 0.5 + 0.5) * resolution, clip.z * 0.5 + 0.5);
}

float edge_function(vec2 a, vec2 b, vec2 c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Whether the point `at` lies on or inside the triangle of atlas positions `w` (its
// doubled signed area `area`), and its barycentric weights `b` there: linear on the map,
// as the rasterizer's with w = 1.
bool covers(vec3 w[3], float area, vec2 at, out vec3 b) {
    b = vec3(edge_function(w[1].xy, w[2].xy, at), edge_function(w[2].xy, w[0].xy, at),
             edge_function(w[0].xy, w[1].xy, at)) / area;
    return all(greaterThanEqual(b, vec3(0.0)));
}

int atlas_index(ivec2 texel) {
    return texel.y * atlas_width + texel.x;
}
