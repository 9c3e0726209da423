#version 450 core
// VPL injection: each VPL adds (flux/pi) * cosLobe(n) at p + cell/2 * n, shared among the
// eight cells around that point by trilinear weights, so the volume changes smoothly as a
// VPL (or the grid) moves instead of jumping when it crosses a cell boundary. Fixed-point
// integer atomics, one channel per integer, so many VPLs in a cell all add up.
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
    vec3 q = (v.position.xyz + 0.5 * cell_size * n - grid_origin) / cell_size - 0.5;  // in cell centres
    ivec3 first = ivec3(floor(q));
    vec3 f = q - vec3(first);
    vec4 lobe = cos_lobe(n) / PI * fixed_point_scale;
    for (int corner = 0; corner < 8; ++corner) {
        ivec3 step = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
        ivec3 cell = first + step;
        if (any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, ivec3(grid_size)))) continue;
        vec3 w3 = mix(1.0 - f, f, vec3(step));
        float weight = w3.x * w3.y * w3.z;
        if (weight <= 0.0) continue;
        int base = ((cell.z * grid_size + cell.y) * grid_size + cell.x) * 12;
        for (int channel = 0; channel < 3; ++channel) {
            vec4 c = lobe * (weight * v.flux[channel]);
            for (int k = 0; k < 4; ++k) {
                atomicAdd(accumulator[base + channel * 4 + k], int(round(c[k])));
            }
        }
    }
}
