#version 450 core
// One VPL per Poisson cell: the flux of every texel in the cell summed (so the VPLs carry
// exactly the RSM's flux), placed at the valid texel nearest the cell's sample point.
// With `exclude`, texels whose surface lies in the box [exclude_low, exclude_high] count
// for nothing (a sun's far field, whose near part another map samples).
#define GROUP 64
layout(local_size_x = GROUP) in;
uniform sampler2D rsm_position;
uniform sampler2D rsm_normal;
uniform sampler2D rsm_flux;
uniform isampler2D cell_ids;
layout(std430, binding = 0) readonly buffer Samples { vec2 sample_texel[]; };  // atlas texels
layout(std430, binding = 1) readonly buffer Bounds { ivec4 bounds[]; };
struct VPL { vec4 position; vec4 normal; vec4 flux; };  // w: valid, surfel area, unused
layout(std430, binding = 2) writeonly buffer VPLs { VPL vpls[]; };

shared vec4 partial_flux[GROUP];   // rgb flux, a surfel area
shared vec2 partial_best[GROUP];   // squared distance, texel index

uniform int cell_count;
uniform bool exclude;
uniform vec3 exclude_low;
uniform vec3 exclude_high;

void main() {
    int cell = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);
    if (cell >= cell_count) return;
    int lane = int(gl_LocalInvocationID.x);
    ivec4 box = bounds[cell];
    int width = box.z - box.x + 1;
    int count = box.z >= box.x ? width * (box.w - box.y + 1) : 0;
    vec2 target = sample_texel[cell];
    vec4 sum = vec4(0.0);
    vec2 best = vec2(1e30, -1.0);
    for (int i = lane; i < count; i += GROUP) {
        ivec2 texel = ivec2(box.x + i % width, box.y + i / width);
        if (texelFetch(cell_ids, texel, 0).r != cell) continue;
        vec4 position = texelFetch(rsm_position, texel, 0);
        if (position.w <= 0.0) continue;
        if (exclude && all(greaterThanEqual(position.xyz, exclude_low)) && all(lessThanEqual(position.xyz, exclude_high)))
            continue;
        sum += vec4(texelFetch(rsm_flux, texel, 0).rgb, texelFetch(rsm_normal, texel, 0).w);
        vec2 d = vec2(texel) + 0.5 - target;
        float dd = dot(d, d);
        if (dd < best.x) best = vec2(dd, float(i));
    }
    partial_flux[lane] = sum;
    partial_best[lane] = best;
    barrier();
    for (int stride = GROUP / 2; stride > 0; stride /= 2) {
        if (lane < stride) {
            partial_flux[lane] += partial_flux[lane + stride];
            if (partial_best[lane + stride].x < partial_best[lane].x) partial_best[lane] = partial_best[lane + stride];
        }
        barrier();
    }
    if (lane == 0) {
        VPL v = VPL(vec4(0.0), vec4(0.0, 0.0, 1.0, 0.0), vec4(0.0));
        if (partial_best[0].y >= 0.0) {
            int i = int(partial_best[0].y);
            ivec2 texel = ivec2(box.x + i % width, box.y + i / width);
            v.position = vec4(texelFetch(rsm_position, texel, 0).xyz, 1.0);
            v.normal = vec4(texelFetch(rsm_normal, texel, 0).xyz, partial_flux[0].a);
            v.flux = vec4(partial_flux[0].rgb, 0.0);
        }
        vpls[cell] = v;
    }
}
