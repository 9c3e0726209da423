#version 450 core
// One view's draw of a range of triangles, cluster by cluster (gpu/mesh_buffer.py): a
// DrawArraysIndirect command per cluster of CLUSTER_TRIANGLES, in the triangles' order,
// with no instance where the cluster's box lies wholly outside one side plane of the
// view's frustum (not its near and far planes: a light map keeps the casters in front of
// its near plane). Each plane test is affine in the world position, so it holds for
// corners behind the eye too. The order is kept: equal depths resolve as in one draw. Bindings 6
// and 7: a raster pass's own buffers stay bound.
layout(local_size_x = 64) in;
layout(std430, binding = 6) readonly buffer Boxes { vec4 boxes[]; };
layout(std430, binding = 7) writeonly buffer Commands { uint commands[]; };  // count, instances, first, base instance, 0
uniform mat4 view_projection;
uniform int first_triangle;
uniform int triangle_count;
uniform int first_command;

void main() {
    int cluster = int(gl_GlobalInvocationID.x);
    int start = cluster * CLUSTER_TRIANGLES;
    if (start >= triangle_count) return;
    vec3 low = boxes[2 * cluster].xyz, high = boxes[2 * cluster + 1].xyz;
    ivec2 left = ivec2(0), right = ivec2(0);  // corners beyond -w and beyond +w, in x and y
    for (int k = 0; k < 8; ++k) {
        vec4 p = view_projection * vec4(mix(low, high, vec3(k & 1, (k >> 1) & 1, k >> 2)), 1.0);
        left += ivec2(lessThan(p.xy, vec2(-p.w)));
        right += ivec2(greaterThan(p.xy, vec2(p.w)));
    }
    bool outside = any(equal(left, ivec2(8))) || any(equal(right, ivec2(8)));
    uint at = uint(5 * (first_command + cluster));  // padded: gpu/mesh_buffer.py CULL_COMMAND_BYTES
    commands[at] = uint(3 * (min(start + CLUSTER_TRIANGLES, triangle_count) - start));
    commands[at + 1u] = outside ? 0u : 1u;
    commands[at + 2u] = uint(3 * (first_triangle + start));
    commands[at + 3u] = 0u;
    commands[at + 4u] = 0u;
}
