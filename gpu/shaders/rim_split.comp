#version 450 core
// Sort the scene's triangles for one paraboloid hemisphere by its rim plane (z = 0 in
// hemisphere space): wholly in front (projected per vertex, dpm.vert), crossing the rim
// (clipped first, dpm.geom), wholly behind (skipped). One index buffer holds both lists,
// the front one from 0 and the crossing one from `capacity`; each is drawn by a
// DrawElementsIndirect command whose count the atomics fill. A first dispatch with
// `reset` writes both commands empty (on the GPU: a buffer upload would wait for the
// previous draws that read them).
//
// With RASTER, a triangle wholly in front whose box on the map spans at most RASTER_SPAN
// texels each way is not listed: this pass rasterises it as the rasterizer would (w = 1:
// depth and weights linear on the map; corners snapped, texel centres on or inside its
// edges), in two stages over the same triangles (paraboloid_raster.glsl). STAGE 1 keeps
// each texel's nearest depth (the bits of a float in [0, 1] order as the floats do),
// STAGE 2 the least triangle at that depth, as an in-order draw's depth test keeps the
// first; rsm_resolve.comp then makes their texels. The rasterizer of a GPU with few raster units
// is slow on the small triangles most of a large scene's are (docs/performance.md,
// "Speed").
#include "vertex_layout.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Vertices { float vertices[]; };  // vertex_layout.glsl
#include "vertex_position.glsl"
layout(std430, binding = 1) buffer Commands { uint commands[]; };  // front, then crossing: 5 uints each
layout(std430, binding = 2) writeonly buffer Lists { uint lists[]; };
uniform mat4 hemisphere_view;
uniform int first_triangle;  // the lights' triangles: first_triangle .. + triangle_count
uniform int triangle_count;
uniform uint capacity;  // indices per list: 3 per triangle
uniform bool reset;
uniform uint first_invocation;  // where this dispatch starts (gpu/context.py dispatch_row)
#ifdef RASTER
uniform vec2 face_origin;
uniform float resolution;
#include "paraboloid_raster.glsl"
layout(std430, binding = 3) coherent buffer NearestDepth { uint nearest_depth[]; };        // inverted
layout(std430, binding = 4) coherent buffer NearestTriangle { uint nearest_triangle[]; };  // inverted

// Rasterise the triangle wholly in front (`corners` in hemisphere space): false where its
// box on the map is too large for this pass.
bool rasterised(int triangle, vec3 corners[3]) {
    vec3 w[3];
    for (int k = 0; k < 3; ++k) w[k] = paraboloid_window(corners[k]);
    vec2 low = min(min(w[0].xy, w[1].xy), w[2].xy), high = max(max(w[0].xy, w[1].xy), w[2].xy);
    ivec2 first = ivec2(ceil(low - 0.5)), last = ivec2(floor(high - 0.5));  // texels whose centres the box holds
    if (any(greaterThan(last - first, ivec2(RASTER_SPAN - 1)))) return false;
    vec2 p[3] = vec2[3](snapped(w[0].xy, first), snapped(w[1].xy, first), snapped(w[2].xy, first));
    float area = edge_function(p[0], p[1], p[2]);
    if (area == 0.0) return true;  // covers no texel: the rasterizer draws none either
    for (int y = first.y; y <= last.y; ++y) {
        for (int x = first.x; x <= last.x; ++x) {
            vec3 b = barycentric(p, area, (vec2(ivec2(x, y) - first) + 0.5) * SUBTEXELS);
            if (any(lessThan(b, vec3(0.0)))) continue;  // on an edge: covered, as by the triangle beside it
            precise float z = clamp(dot(b, vec3(w[0].z, w[1].z, w[2].z)), 0.0, 1.0);  // both stages alike
            uint depth = ~floatBitsToUint(z);
            int at = atlas_index(ivec2(x, y));
#if STAGE == 1
            if (depth > nearest_depth[at]) atomicMax(nearest_depth[at], depth);  // most lose: read first
#else
            if (depth >= nearest_depth[at] && ~uint(triangle) > nearest_triangle[at])  // at the nearest
                atomicMax(nearest_triangle[at], ~uint(triangle));
#endif
        }
    }
    return true;
}
#endif

void main() {
    uint i = first_invocation + gl_GlobalInvocationID.x;
    if (reset) {
        // (count, instances, first index, base vertex, base instance) of both commands.
        if (i < 10u) commands[i] = i % 5u == 1u ? 1u : (i == 7u ? capacity : 0u);
        return;
    }
    if (int(i) >= triangle_count) return;
    int triangle = first_triangle + int(i);
    int in_front = 0;
    vec3 corners[3];
    for (int k = 0; k < 3; ++k) {
        corners[k] = (hemisphere_view * vec4(vertex_position(triangle * 3 + k), 1.0)).xyz;
        if (corners[k].z >= 0.0) in_front += 1;
    }
    if (in_front == 0) return;
    bool front = in_front == 3;
#ifdef RASTER
    if (front && rasterised(triangle, corners)) return;
#if STAGE == 2
    return;  // the first stage listed what this one does not rasterise
#endif
#endif
    uint slot = atomicAdd(commands[front ? 0 : 5], 3u) + (front ? 0u : capacity);
    uint first = uint(triangle * 3);
    for (uint k = 0u; k < 3u; ++k) lists[slot + k] = first + k;
}
