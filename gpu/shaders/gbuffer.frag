#version 450 core
// Camera G-buffer, first half: the depth and, per pixel, the number of the triangle seen
// (its top bit set where its front faces the camera) and with SURFACE_IMAGES the colour of
// its image there; gbuffer_resolve.comp makes the surface texels from them. A raster pass
// spends its time on what each fragment reads and writes, which a GPU with few raster
// units does slowly (docs/performance.md, "Raster passes"); the image is sampled here,
// where the pixel's footprint on it is known.
// With CUT_OUT a pixel the surface does not cover (surface.glsl) shows what is behind it.
#include "surface.glsl"
#include "surface_vertices.glsl"
layout(location = 0) out uint out_triangle;
#ifdef SURFACE_IMAGES
layout(location = 1) out vec4 out_image_colour;
#endif

void main() {
#ifdef CUT_OUT
    if (!surface_covers(surface_vec4(VERTEX_ALBEDO), surface_point(), surface_vec4(VERTEX_TINT), gl_FragCoord.xy))
        discard;
#endif
    out_triangle = uint(surface_triangle) | (gl_FrontFacing ? 0x80000000u : 0u);
#ifdef SURFACE_IMAGES
    float layer = vertices[3 * VERTEX_FLOATS * surface_triangle + VERTEX_SURFACE + 2];  // one a triangle
    out_image_colour = vec4(layer < -0.5 ? vec3(1.0) : surface_image(surface_point()), 1.0);
#endif
}
