#version 450 core
// VPL injection: each VPL adds (flux/pi) * cosLobe(n) at p + cell/2 * n, shared among the
// eight cells around that point by trilinear weights, so the volume changes smoothly as a
// VPL (or the grid) moves instead of jumping when it crosses a cell boundary. Fixed-point
// integer atomics, one channel per integer, so many VPLs in a cell all add up. A glossy
// VPL (emitter.glsl glossy_lobe) adds its lobe around its axis: the same first coefficient,
// the next ones times its mean cosine over the cosine's 2/3, taken as a Phong lobe's of
// the same spread, (k + 1) / (k + 2) for k = 1 / (2 alpha^2).
// A workgroup's VPLs come from one patch of the light's map and fall into a few cells:
// they add up in shared memory first (a small table of cells), and each cell goes to the
// volume with one atomic per channel; a cell the full table cannot take goes straight.
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

const int TABLE = 128;  // cells a workgroup gathers in shared memory
shared int table_cells[TABLE];
shared int table_sums[TABLE * 12];

// Add the fixed-point SH coefficients r, g, b of `cell` into the table, or into the volume
// when the table has no room for the cell.
void add(int cell, ivec4 r, ivec4 g, ivec4 b) {
    int slot = int(uint(cell) * 2654435761u % uint(TABLE));
    for (int probe = 0; probe < 8; ++probe) {
        int held = atomicCompSwap(table_cells[slot], -1, cell);
        if (held == -1 || held == cell) {
            for (int k = 0; k < 4; ++k) {
                atomicAdd(table_sums[slot * 12 + k], r[k]);
                atomicAdd(table_sums[slot * 12 + 4 + k], g[k]);
                atomicAdd(table_sums[slot * 12 + 8 + k], b[k]);
            }
            return;
        }
        slot = (slot + 1) % TABLE;
    }
    for (int k = 0; k < 4; ++k) {
        atomicAdd(accumulator[cell * 12 + k], r[k]);
        atomicAdd(accumulator[cell * 12 + 4 + k], g[k]);
        atomicAdd(accumulator[cell * 12 + 8 + k], b[k]);
    }
}

void main() {
    uint local = gl_LocalInvocationIndex;
    for (uint slot = local; slot < uint(TABLE); slot += 64u) {
        table_cells[slot] = -1;
        for (int k = 0; k < 12; ++k) table_sums[slot * 12u + uint(k)] = 0;
    }
    barrier();
    int index = int(gl_GlobalInvocationID.x);
    if (index < vpl_count && vpls[index].position.w > 0.0) {
        VPL v = vpls[index];
        vec3 n = v.normal.xyz;
        vec3 q = (v.position.xyz + cell_size * n - grid_origin) / cell_size - 0.5;  // in cell centres
        ivec3 first = ivec3(floor(q));
        vec3 f = q - vec3(first);
        vec4 lobe = cos_lobe(n) / PI * fixed_point_scale;
        if (v.flux.w < 0.0) {
            float k = 0.5 / (v.flux.w * v.flux.w);
            lobe.yzw *= 1.5 * (k + 1.0) / (k + 2.0);
        }
        for (int corner = 0; corner < 8; ++corner) {
            ivec3 step = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
            ivec3 cell = first + step;
            if (any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, ivec3(grid_size)))) continue;
            vec3 w3 = mix(1.0 - f, f, vec3(step));
            float weight = w3.x * w3.y * w3.z;
            if (weight <= 0.0) continue;
            vec4 c = lobe * weight;
            add((cell.z * grid_size + cell.y) * grid_size + cell.x, ivec4(round(c * v.flux.r)),
                ivec4(round(c * v.flux.g)), ivec4(round(c * v.flux.b)));
        }
    }
    barrier();
    for (uint slot = local; slot < uint(TABLE); slot += 64u) {
        int cell = table_cells[slot];
        if (cell < 0) continue;
        for (int k = 0; k < 12; ++k) {
            int value = table_sums[slot * 12u + uint(k)];
            if (value != 0) atomicAdd(accumulator[cell * 12 + k], value);
        }
    }
}
