#version 450 core
// The light grid (gpu/light_grid.py): every cell centre sums the light of every emitter that
// sees it (a march through the occupancy of every level, each part of the segment in the
// finest level that holds it: a wall outside the cell's own grid still stands), as the
// irradiance of six surfaces facing +x, -x, +y, -y, +z and -z (an ambient cube), each into
// its own block of the volume along z.
// The emitters are clusters of every octave (emitter_compact.comp); a cell takes a light cut
// of them: each cluster where it stands far enough from the cell centre and the one twice
// as wide holding it does not (gpu/light_grid.py NEAR_SIZES), so every emitter is counted
// once, near ones in the finest clusters and far ones in wide ones. A cluster with a normal
// lights the six faces as a square (emitter.glsl square_faces), a glossy one or one without
// a normal as a point.
// A workgroup is one cell, its lanes share the emitters and add up their sums at the end:
// cells alone are too few to fill a GPU. One dispatch adds the emitters [first_emitter,
// first_emitter + batch) to what the ones before left: llvmpipe ends a loop nest after
// 65,535 iterations in all, marches included. With UNSHADOWED, the light every emitter
// would give without occluders goes beside it into `unshadowed` (gpu/emitter_shadows.py
// takes their ratio). With ROOMS a cell gathers only the clusters of its own room
// (`receiving` holds 1 + its room: light_grid_rooms.comp).
#include "common.glsl"
#include "emitter.glsl"
#include "levels_march.glsl"
#include "cluster_key.glsl"
#define LANES 64
layout(local_size_x = LANES) in;
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 1) readonly buffer Count { int emitter_count; };
layout(rgba32f, binding = 0) uniform image3D irradiance;
#if UNSHADOWED
layout(rgba32f, binding = 1) uniform image3D unshadowed;
#define SUMS 12
#else
#define SUMS 6
#endif
uniform vec3 grid_origin;
uniform float cell_size;
uniform int grid_size;
uniform int first_emitter;
uniform int batch;
uniform usampler3D receiving;  // the cells a lookup can read (light_grid_receiving.comp, not 0): the others are skipped
uniform int layer;             // this grid's block of it along z
uniform vec3 cluster_origins[CLUSTER_LEVELS];  // the clusters' levels (emitter_cluster.comp)
uniform float cluster_cells[CLUSTER_LEVELS];
uniform int cluster_grid_size;

shared vec3 sums[SUMS][LANES];  // +x, -x, +y, -y, +z, -z (then the same unshadowed)

// Whether the cluster cell of `level`, `cell` (in cells `octave` octaves wide) is near `p`.
bool near_cluster(vec3 p, int level, ivec3 cell, int octave) {
    float size = cluster_cells[level] * float(1 << octave);
    vec3 low = cluster_origins[level] + vec3(cell) * size;
    return length(max(max(low - p, p - low - size), 0.0)) <= NEAR_SIZES * size;
}

// Whether the cluster `e` counts at `p` in `room`: it is in the cut at p (near p stand its
// narrower clusters, where the wider one holding it is far, that one does) and in that room.
bool in_cut_and_room(Emitter e, vec3 p, int room) {
#if DEPTH == 1 && !defined(ROOMS)
    return true;  // one octave, one room: every cluster counts
#else
    int octave = cluster_word_octave(e.position.w), level, bin, own_room;
    ivec3 cell;
    cluster_cell(cluster_word_key(e.position.w), cluster_grid_size, CLUSTER_LEVELS, level, cell, bin, own_room);
#if DEPTH > 1
    if ((octave != 0 && near_cluster(p, level, cell, octave))
        || (octave != DEPTH - 1 && !near_cluster(p, level, cell >> 1, octave + 1)))
        return false;
#endif
    return own_room == room;
#endif
}

void main() {
    int index = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);  // context.py run_workgroups
    if (index >= grid_size * grid_size * grid_size) return;
    int lane = int(gl_LocalInvocationID.x);
    ivec3 cell = ivec3(index % grid_size, (index / grid_size) % grid_size, index / (grid_size * grid_size));
    uint marked = texelFetch(receiving, cell + ivec3(0, 0, layer * grid_size), 0).r;
    if (marked == 0u) {
        if (lane < 6 && first_emitter == 0) imageStore(irradiance, ivec3(cell.xy, cell.z + lane * grid_size), vec4(0.0));
#if UNSHADOWED
        else if (lane < 12 && first_emitter == 0)
            imageStore(unshadowed, ivec3(cell.xy, cell.z + (lane - 6) * grid_size), vec4(0.0));
#endif
        return;
    }
    vec3 centre = grid_origin + (vec3(cell) + 0.5) * cell_size;
#ifdef ROOMS
    int room = int(marked) - 1;
#else
    int room = 0;
#endif
    vec3 facing[SUMS];
    for (int k = 0; k < SUMS; ++k) facing[k] = vec3(0.0);
    int last = min(first_emitter + batch, emitter_count);
    for (int j = first_emitter + lane; j < last; j += LANES) {
        Emitter e = emitters[j];
        if (!in_cut_and_room(e, centre, room)) continue;
        vec3 light, plus, minus;  // the light on surfaces facing +axis and -axis: light * plus, light * minus
        if (square_emitter(e)) {
            square_faces(e, centre, light, plus, minus);
        } else {
            vec3 d = centre - e.position.xyz;
            light = shared_emitter_light(e, d, singularity_bound, singularity_bound);
            vec3 w = normalize(d);
            plus = max(-w, 0.0);
            minus = max(w, 0.0);
        }
        if (max(light.r, max(light.g, light.b)) <= 0.0 || max(dot(plus, plus), dot(minus, minus)) <= 0.0) continue;
#if UNSHADOWED
        for (int axis = 0; axis < 3; ++axis) {
            facing[6 + 2 * axis] += light * plus[axis];
            facing[6 + 2 * axis + 1] += light * minus[axis];
        }
#endif
        if (levels_blocked(e.position.xyz + EMITTER_OFFSET * level_voxels[first_level] * e.normal.xyz, centre,
                           e.position.xyz))
            continue;
        for (int axis = 0; axis < 3; ++axis) {
            facing[2 * axis] += light * plus[axis];
            facing[2 * axis + 1] += light * minus[axis];
        }
    }
    for (int k = 0; k < SUMS; ++k) sums[k][lane] = facing[k];
    barrier();
    for (int stride = LANES / 2; stride > 0; stride /= 2) {
        if (lane < stride)
            for (int k = 0; k < SUMS; ++k) sums[k][lane] += sums[k][lane + stride];
        barrier();
    }
    if (lane < 6) {
        ivec3 at = ivec3(cell.xy, cell.z + lane * grid_size);
        vec4 before = first_emitter == 0 ? vec4(0.0) : imageLoad(irradiance, at);
        imageStore(irradiance, at, before + vec4(sums[lane][0], 0.0));
    }
#if UNSHADOWED
    else if (lane < 12) {
        ivec3 at = ivec3(cell.xy, cell.z + (lane - 6) * grid_size);
        vec4 before = first_emitter == 0 ? vec4(0.0) : imageLoad(unshadowed, at);
        imageStore(unshadowed, at, before + vec4(sums[lane][0], 0.0));
    }
#endif
}
