#version 450 core
// VPL injection: each VPL adds (flux/pi) * cosLobe(n) to the cell holding p + cell/2 * n.
// Fixed-point integer atomics, one channel per integer, so many VPLs in a cell all add up.
#include "common.glsl"
layout(local_size_x = 64) in;
struct VPL { vec4 position; vec4 normal; vec4 flux; };
layout(std430, binding = 0) readonly buffer VPLs { VPL vpls[]; };
layout(std430, binding = 1) buffer Accumulator { int accumulator[]; };  // cell * 12 + channel * 4 + k
uniform int vpl_count;
uniform vec3 grid_origin;
uniform float cell_size;
uniform int grid_size;
uniform float fixed_point_scale;

void main() {
    int index = int(gl_GlobalInvocationID.x);
    if (index >= vpl_count) return;
    VPL v = vpls[index];
    if (v.position.w <= 0.0) return;
    vec3 n = v.normal.xyz;
    ivec3 cell = ivec3(floor((v.position.xyz + 0.5 * cell_size * n - grid_origin) / cell_size));
    if (any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, ivec3(grid_size)))) return;
    int base = ((cell.z * grid_size + cell.y) * grid_size + cell.x) * 12;
    vec4 lobe = cos_lobe(n) / PI * fixed_point_scale;
    for (int channel = 0; channel < 3; ++channel) {
        vec4 c = lobe * v.flux[channel];
        for (int k = 0; k < 4; ++k) {
            atomicAdd(accumulator[base + channel * 4 + k], int(round(c[k])));
        }
    }
}
