#version 450 core
// The emitter grid's textures (gpu/emitter_grid.py, seed 002): at every cell centre of
// the finest level, the colour sum (the irradiance each emitter gives a surface facing
// it, summed) and the direction sum (each one's luminance times its
// unit direction toward the emitter) kept as its positive and negative halves along each
// axis, which are the irradiance of the six surfaces facing the axes. Every emitter counts once, through its cluster at
// the coarsest level whose cell is still apart from the centre's: the 27 finest cells
// around the centre, then at each level the children of the parent level's 27
// neighbours that are not neighbours themselves (189 cells), up to the level of two
// cells a side. A cluster lights as one isotropic point at its flux-weighted position,
// its 1/r² bounded as its emitters' flux-weighted mean area says (their sum would dim
// a cluster of many).
#include "common.glsl"
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(std430, binding = 1) readonly buffer Clusters { float clusters[]; };
layout(rgba32f, binding = 0) uniform writeonly image3D colour_sum;
layout(rgba32f, binding = 1) uniform writeonly image3D direction_positive;
layout(rgba32f, binding = 2) uniform writeonly image3D direction_negative;
uniform int level_offsets[LEVELS];
uniform vec3 grid_origin;
uniform float cell_size;
uniform int grid_size;
uniform float singularity_bound;
uniform vec3 luminance_weights;

void add_cluster(int at, vec3 centre, inout vec3 colour, inout vec3 positive, inout vec3 negative) {
    float weight = clusters[at + 3];
    if (!(weight > 0.0)) return;
    vec3 position = vec3(clusters[at + 4], clusters[at + 5], clusters[at + 6]) / weight;
    vec3 d = position - centre;
    float r2 = dot(d, d);
    vec3 flux = vec3(clusters[at], clusters[at + 1], clusters[at + 2]);
    vec3 light = flux / (4.0 * PI) / (r2 + singularity_bound * clusters[at + 7] / weight / PI + 1e-30);
    colour += light;
    vec3 w = d * inversesqrt(max(r2, 1e-30));
    float luminance = dot(light, luminance_weights);
    positive += luminance * max(w, vec3(0.0));
    negative += luminance * max(-w, vec3(0.0));
}

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(cell, ivec3(grid_size)))) return;
    vec3 centre = grid_origin + (vec3(cell) + 0.5) * cell_size;
    vec3 colour = vec3(0.0), positive = vec3(0.0), negative = vec3(0.0);
    for (int z = -1; z <= 1; ++z)
        for (int y = -1; y <= 1; ++y)
            for (int x = -1; x <= 1; ++x) {
                ivec3 c = cell + ivec3(x, y, z);
                if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, ivec3(grid_size)))) continue;
                add_cluster(CLUSTER_FLOATS * (c.x + grid_size * (c.y + grid_size * c.z)), centre, colour, positive, negative);
            }
    for (int level = 0; level < LEVELS - 1; ++level) {
        int size = grid_size >> level;
        ivec3 own = cell >> level;
        ivec3 low = max(((own >> 1) - 1) * 2, ivec3(0));
        ivec3 high = min(((own >> 1) + 1) * 2 + 1, ivec3(size - 1));
        for (int z = low.z; z <= high.z; ++z)
            for (int y = low.y; y <= high.y; ++y)
                for (int x = low.x; x <= high.x; ++x) {
                    ivec3 c = ivec3(x, y, z);
                    ivec3 apart = abs(c - own);
                    if (max(apart.x, max(apart.y, apart.z)) <= 1) continue;
                    add_cluster(CLUSTER_FLOATS * (level_offsets[level] + c.x + size * (c.y + size * c.z)), centre,
                                colour, positive, negative);
                }
    }
    imageStore(colour_sum, cell, vec4(colour, 0.0));
    imageStore(direction_positive, cell, vec4(positive, 0.0));
    imageStore(direction_negative, cell, vec4(negative, 0.0));
}
