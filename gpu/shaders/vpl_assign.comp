#version 450 core
// Poisson cells: each texel of one RSM face joins the nearest Poisson-disk sample point.
// Writes the cell id per texel and grows each cell's bounding box (integer atomics).
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32i, binding = 0) uniform writeonly iimage2D cell_ids;
layout(std430, binding = 0) readonly buffer Points { vec2 points[]; };        // in [0, 1)^2
layout(std430, binding = 1) readonly buffer Buckets { int bucket_start[]; };  // grid * grid + 1
layout(std430, binding = 2) buffer Bounds { ivec4 bounds[]; };                // min xy, max xy
uniform ivec2 face_origin;
uniform int resolution;
uniform int first_cell;
uniform int point_count;
uniform int grid;

void main() {
    ivec2 local = ivec2(gl_GlobalInvocationID.xy);
    if (local.x >= resolution || local.y >= resolution) return;
    vec2 q = (vec2(local) + 0.5) / float(resolution);
    ivec2 b = min(ivec2(q * float(grid)), ivec2(grid - 1));
    int best = -1;
    float best_d = 1e30;
    for (int by = max(b.y - 2, 0); by <= min(b.y + 2, grid - 1); ++by) {
        for (int bx = max(b.x - 2, 0); bx <= min(b.x + 2, grid - 1); ++bx) {
            int bucket = by * grid + bx;
            for (int i = bucket_start[bucket]; i < bucket_start[bucket + 1]; ++i) {
                vec2 d = points[i] - q;
                float dd = dot(d, d);
                if (dd < best_d) { best_d = dd; best = i; }
            }
        }
    }
    if (best < 0) {  // a hole wider than the search window: look at every point
        for (int i = 0; i < point_count; ++i) {
            vec2 d = points[i] - q;
            float dd = dot(d, d);
            if (dd < best_d) { best_d = dd; best = i; }
        }
    }
    int cell = first_cell + best;
    ivec2 texel = face_origin + local;
    imageStore(cell_ids, texel, ivec4(cell));
    atomicMin(bounds[cell].x, texel.x);
    atomicMin(bounds[cell].y, texel.y);
    atomicMax(bounds[cell].z, texel.x);
    atomicMax(bounds[cell].w, texel.y);
}
