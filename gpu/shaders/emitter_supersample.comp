#version 450 core
// The emitter grid's three textures at twice their resolution, for the super-sampled read
// (emitter_shade.comp INTERPOLATION 2). The mean of eight trilinear reads a quarter cell
// around a point is, along each axis, linear between the points a quarter cell either
// side of the cell centres (and constant beyond the outermost, as the reads clamp): one
// trilinear read of textures whose texel centres are those points gives the same mean.
// Each such texel holds 3/4 of its own cell and 1/4 of the neighbour on its side (its own
// cell again at the edge), along each axis.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
uniform sampler3D colour_sum;
uniform sampler3D direction_positive;
uniform sampler3D direction_negative;
layout(rgba32f, binding = 0) uniform writeonly image3D fine_colour_sum;
layout(rgba32f, binding = 1) uniform writeonly image3D fine_direction_positive;
layout(rgba32f, binding = 2) uniform writeonly image3D fine_direction_negative;
uniform int grid_size;  // the coarse textures' cells a side

vec4 upsampled(sampler3D coarse, ivec3 own, ivec3 other) {
    vec4 sum = vec4(0.0);
    for (int k = 0; k < 8; ++k) {
        ivec3 pick = ivec3(k & 1, (k >> 1) & 1, k >> 2);  // 1: the neighbour along that axis
        vec3 weight = mix(vec3(0.75), vec3(0.25), vec3(pick));
        sum += weight.x * weight.y * weight.z * texelFetch(coarse, own + pick * (other - own), 0);
    }
    return sum;
}

void main() {
    ivec3 fine = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(fine, ivec3(2 * grid_size)))) return;
    ivec3 own = fine >> 1;
    ivec3 other = clamp(own + 2 * (fine & 1) - 1, ivec3(0), ivec3(grid_size - 1));
    imageStore(fine_colour_sum, fine, upsampled(colour_sum, own, other));
    imageStore(fine_direction_positive, fine, upsampled(direction_positive, own, other));
    imageStore(fine_direction_negative, fine, upsampled(direction_negative, own, other));
}
