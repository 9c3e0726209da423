#version 450 core
// The light grid (gpu/light_grid.py): every cell centre sums the light of every emitter that
// sees it (a march through the occupancy), as the irradiance of six surfaces facing +x, -x,
// +y, -y, +z and -z (an ambient cube), each into its own block of the volume along z.
// One dispatch adds the emitters [first_emitter, first_emitter + batch) to what the ones
// before left: llvmpipe ends a loop nest after 65,535 iterations in all, marches included.
#include "common.glsl"
#include "emitter.glsl"
#include "occupancy.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 1) readonly buffer Count { int emitter_count; };
layout(rgba32f, binding = 0) uniform image3D irradiance;
uniform usampler3D occupancy;
uniform vec3 grid_origin;
uniform float cell_size;
uniform int grid_size;
uniform int voxels_per_cell;
uniform int first_emitter;
uniform int batch;

void main() {
    int index = int(gl_GlobalInvocationID.x);
    ivec3 cell = ivec3(index % grid_size, (index / grid_size) % grid_size, index / (grid_size * grid_size));
    vec3 centre = grid_origin + (vec3(cell) + 0.5) * cell_size;
    float voxel = cell_size / float(voxels_per_cell);
    vec3 centre_voxels = (centre - grid_origin) / voxel;
    vec3 positive[3] = vec3[3](vec3(0.0), vec3(0.0), vec3(0.0));  // facing +x, +y, +z
    vec3 negative[3] = vec3[3](vec3(0.0), vec3(0.0), vec3(0.0));
    if (index >= grid_size * grid_size * grid_size) return;
    for (int j = first_emitter; j < min(first_emitter + batch, emitter_count); ++j) {
        Emitter e = emitters[j];
        vec3 d = centre - e.position.xyz;
        vec3 light = emitter_light(e, d);
        if (max(light.r, max(light.g, light.b)) <= 0.0) continue;
        vec3 from = (e.position.xyz - grid_origin) / voxel;
        if (segment_blocked(occupancy, from + 0.75 * e.normal.xyz, centre_voxels, from, 1.0))
            continue;
        vec3 w = normalize(d);
        for (int axis = 0; axis < 3; ++axis) {
            positive[axis] += light * max(0.0, -w[axis]);
            negative[axis] += light * max(0.0, w[axis]);
        }
    }
    for (int axis = 0; axis < 3; ++axis) {
        ivec3 at = ivec3(cell.xy, cell.z + (2 * axis) * grid_size);
        ivec3 opposite = ivec3(cell.xy, cell.z + (2 * axis + 1) * grid_size);
        bool first = first_emitter == 0;
        imageStore(irradiance, at, vec4(positive[axis], 0.0) + (first ? vec4(0.0) : imageLoad(irradiance, at)));
        imageStore(irradiance, opposite, vec4(negative[axis], 0.0) + (first ? vec4(0.0) : imageLoad(irradiance, opposite)));
    }
}
