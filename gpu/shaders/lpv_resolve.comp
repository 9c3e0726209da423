#version 450 core
// Fixed-point accumulators to float SH volumes: CHANNELS volumes of 4 coefficients.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(std430, binding = 0) readonly buffer Accumulator { int accumulator[]; };
layout(rgba32f, binding = 0) uniform writeonly image3D volume0;
#if CHANNELS == 3
layout(rgba32f, binding = 1) uniform writeonly image3D volume1;
layout(rgba32f, binding = 2) uniform writeonly image3D volume2;
#endif
uniform int size;
uniform float inverse_scale;

vec4 coefficients(int base) {
    return vec4(accumulator[base], accumulator[base + 1], accumulator[base + 2], accumulator[base + 3]) * inverse_scale;
}

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(cell, ivec3(size)))) return;
    int base = ((cell.z * size + cell.y) * size + cell.x) * 4 * CHANNELS;
    imageStore(volume0, cell, coefficients(base));
#if CHANNELS == 3
    imageStore(volume1, cell, coefficients(base + 4));
    imageStore(volume2, cell, coefficients(base + 8));
#endif
}
