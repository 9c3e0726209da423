// The surface at a fragment of a raster pass, read from the vertex buffer
// (triangle_corners.glsl) by the triangle's number and the fragment's barycentric weights:
// the rasterizer interpolates two floats, not every attribute, which on a GPU with few
// raster units costs more than the whole fragment (docs/performance.md, "Raster passes").
#include "surface.glsl"
#include "triangle_corners.glsl"
#ifdef RESOLVED_SURFACE
int surface_triangle;  // set by a pass that finds its surface itself (rsm_resolve.comp)
vec2 surface_weights;
vec2 surface_weights_dx, surface_weights_dy;  // their change a pixel along x and along y
#else
flat in int surface_triangle;
in vec2 surface_weights;  // the weights of the triangle's second and third corners
#endif

float surface_float(int offset) {
    return corner_mix(surface_triangle, surface_weights, offset);
}

vec3 surface_vec3(int offset) {
    return corner_mix3(surface_triangle, surface_weights, offset);
}

vec4 surface_vec4(int offset) {
    return corner_mix4(surface_triangle, surface_weights, offset);
}

// The surface coordinate here and its change a pixel along x and along y, from the
// derivatives of the weights (inputs, which helper invocations have too: llvmpipe's give
// no storage reads, so a derivative of what the fragment reads is wrong where a pixel
// quad crosses a triangle's edge) and the corners' coordinates.
SurfacePoint surface_point() {
    int at = 3 * VERTEX_FLOATS * surface_triangle + VERTEX_SURFACE;
    vec2 c0 = vec2(vertices[at], vertices[at + 1]);
    vec2 c1 = vec2(vertices[at + VERTEX_FLOATS], vertices[at + VERTEX_FLOATS + 1]) - c0;
    vec2 c2 = vec2(vertices[at + 2 * VERTEX_FLOATS], vertices[at + 2 * VERTEX_FLOATS + 1]) - c0;
#ifdef RESOLVED_SURFACE
    vec2 dx = surface_weights_dx, dy = surface_weights_dy;
#else
    vec2 dx = dFdx(surface_weights), dy = dFdy(surface_weights);
#endif
    return SurfacePoint(surface_vec4(VERTEX_SURFACE), c1 * dx.x + c2 * dx.y, c1 * dy.x + c2 * dy.y);
}
