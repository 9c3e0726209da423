#version 450 core
// Every texel of a paraboloid face after rim_split.comp rasterised its small triangles
// (RASTER): where it kept one, that triangle's surface where the texel's centre lies on
// the map, as rsm.frag would write it; elsewhere empty (this pass is the maps' clear).
// The rasterizer then draws the triangles that pass listed over them (rsm.frag with
// RASTERISED). A compute pass, not a fragment one: a GPU with few raster units shades
// fragments on few of its cores. The weights' change along x and y is the triangle's own
// on the map (linear there).
#define RESOLVED_SURFACE
#include "rsm_surface.glsl"
#include "paraboloid_raster.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 3) readonly buffer NearestDepth { uint nearest_depth[]; };        // inverted
layout(std430, binding = 4) readonly buffer NearestTriangle { uint nearest_triangle[]; };  // inverted
layout(rgba32f, binding = 0) uniform writeonly image2D rsm_position;
layout(rgba32f, binding = 1) uniform writeonly image2D rsm_normal;
layout(rgba32f, binding = 2) uniform writeonly image2D rsm_flux;
uniform mat4 hemisphere_view;  // world to hemisphere space

void main() {
    ivec2 local = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(local, ivec2(resolution)))) return;
    ivec2 texel = ivec2(face_origin) + local;
    uint kept = nearest_triangle[atlas_index(texel)];
    vec4 position = vec4(0.0), normal = vec4(0.0), flux = vec4(0.0);
    if (kept != 0u) {
        surface_triangle = int(~kept);
        vec2 w[3];
        for (int k = 0; k < 3; ++k)
            w[k] = paraboloid_window((hemisphere_view * vec4(vertex_position(3 * surface_triangle + k), 1.0)).xyz).xy;
        float area = edge_function(w[0], w[1], w[2]);
        vec2 centre = vec2(texel) + 0.5;
        surface_weights = barycentric(w, area, centre).yz;
        surface_weights_dx = vec2(w[2].y - w[0].y, w[0].y - w[1].y) / area;
        surface_weights_dy = vec2(w[0].x - w[2].x, w[1].x - w[0].x) / area;
        surface_rsm_texel(surface_vec4(VERTEX_ALBEDO), surface_point(), centre, position, normal, flux);
    }
    imageStore(rsm_position, texel, position);
    imageStore(rsm_normal, texel, normal);
    imageStore(rsm_flux, texel, flux);
}
