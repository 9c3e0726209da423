#version 450 core
// Geometry volume: every RSM surfel adds its blocking potential clamp(A / cell^2, 0, 1)
// as a cosine lobe around its normal, in a grid whose cell centres sit on LPV cell corners,
// shared among the eight cells around it by trilinear weights (the volume moves smoothly
// with the surfaces and the grid). One texel of each `stride` x `stride` block stands for
// the block (its area times stride^2): the volume's cells are far coarser than the maps'
// texels, and eight atomics a texel of a full map cost more than the rest of the frame.
#include "common.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
uniform sampler2D rsm_position;
uniform sampler2D rsm_normal;
layout(std430, binding = 0) buffer Accumulator { int accumulator[]; };  // cell * 4 + k
uniform ivec2 atlas_size;
uniform int stride;
uniform vec3 grid_origin;
uniform float cell_size;
uniform int grid_size;  // LPV cells per side; the geometry volume has one more
uniform float fixed_point_scale;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy) * stride + stride / 2;
    if (texel.x >= atlas_size.x || texel.y >= atlas_size.y) return;
    vec4 p = texelFetch(rsm_position, texel, 0);
    if (p.w <= 0.0) return;
    vec4 n = texelFetch(rsm_normal, texel, 0);
    int size = grid_size + 1;
    vec3 q = (p.xyz - grid_origin) / cell_size;  // geometry cell centres at whole numbers
    ivec3 first = ivec3(floor(q));
    vec3 f = q - vec3(first);
    vec4 c = cos_lobe(n.xyz) * clamp(n.w * float(stride * stride) / (cell_size * cell_size), 0.0, 1.0)
        * fixed_point_scale;
    for (int corner = 0; corner < 8; ++corner) {
        ivec3 step = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
        ivec3 cell = first + step;
        if (any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, ivec3(size)))) continue;
        vec3 w3 = mix(1.0 - f, f, vec3(step));
        float weight = w3.x * w3.y * w3.z;
        if (weight <= 0.0) continue;
        int base = ((cell.z * size + cell.y) * size + cell.x) * 4;
        for (int k = 0; k < 4; ++k) {
            atomicAdd(accumulator[base + k], int(round(weight * c[k])));
        }
    }
}
