#version 450 core
// One coarser level of the emitter grid's clusters (gpu/emitter_grid.py): each cell sums
// its eight children of the level below.
layout(local_size_x = 64) in;
layout(std430, binding = 1) buffer Clusters { float clusters[]; };
uniform int fine_offset;    // the finer level's first cell
uniform int coarse_offset;  // this level's first cell
uniform int coarse_size;    // this level's cells along a side

void main() {
    int index = int(gl_GlobalInvocationID.x);
    if (index >= coarse_size * coarse_size * coarse_size) return;
    ivec3 cell = ivec3(index % coarse_size, (index / coarse_size) % coarse_size, index / (coarse_size * coarse_size));
    int fine_size = 2 * coarse_size;
    float sum[CLUSTER_FLOATS];
    for (int k = 0; k < CLUSTER_FLOATS; ++k) sum[k] = 0.0;
    for (int child = 0; child < 8; ++child) {
        ivec3 c = 2 * cell + ivec3(child & 1, (child >> 1) & 1, child >> 2);
        int at = CLUSTER_FLOATS * (fine_offset + c.x + fine_size * (c.y + fine_size * c.z));
        for (int k = 0; k < CLUSTER_FLOATS; ++k) sum[k] += clusters[at + k];
    }
    int at = CLUSTER_FLOATS * (coarse_offset + index);
    for (int k = 0; k < CLUSTER_FLOATS; ++k) clusters[at + k] = sum[k];
}
