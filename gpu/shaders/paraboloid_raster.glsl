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

// The barycentric weights of the point `at` in the triangle of map positions `p` (its
// doubled signed area `area`): linear on the map, as the rasterizer's with w = 1.
vec3 barycentric(vec2 p[3], float area, vec2 at) {
    return vec3(edge_function(p[1], p[2], at), edge_function(p[2], p[0], at), edge_function(p[0], p[1], at)) / area;
}

const float SUBTEXELS = 256.0;
// A map position in 1/SUBTEXELS of a texel from the texel `origin`, rounded as the
// rasterizer snaps a vertex: in a small triangle's box the edge functions of such
// integers are exact in floats, so a texel centre on an edge two triangles share is
// covered by both, never by neither.
vec2 snapped(vec2 position, ivec2 origin) {
    return round((position - vec2(origin)) * SUBTEXELS);
}

int atlas_index(ivec2 texel) {
    return texel.y * atlas_width + texel.x;
}
