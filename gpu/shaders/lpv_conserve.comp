#version 450 core
// Before a propagation step, scale each cell's SH intensity (per colour) so the faces'
// estimates send out no more flux than the cell holds (its SH integral, c0 * 2 sqrt(pi)):
// a 2-band lobe is negative in places, and clamping those to zero in the face estimates
// would create light (a cosine lobe's first step gained 14 %).
#include "common.glsl"
#include "lpv_faces.glsl"
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(rgba32f, binding = 0) uniform image3D volume_r;
layout(rgba32f, binding = 1) uniform image3D volume_g;
layout(rgba32f, binding = 2) uniform image3D volume_b;
uniform int grid_size;

vec4 conserved(vec4 sh) {
    float held = max(sh.x, 0.0) * 2.0 * sqrt(PI);
    float sent = outgoing_flux(sh);
    return sent > held * 1.000001 ? sh * (held / sent) : sh;  // float32 sums of an isotropic cell reach 4 pi I
}

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(cell, ivec3(grid_size)))) return;
    imageStore(volume_r, cell, conserved(imageLoad(volume_r, cell)));
    imageStore(volume_g, cell, conserved(imageLoad(volume_g, cell)));
    imageStore(volume_b, cell, conserved(imageLoad(volume_b, cell)));
}
