#version 450 core
// One propagation step (METHOD §7): every cell gathers from its six neighbours through the
// far face and the four side faces, reading one grid and writing another (ping-pong), and
// adds what it gathered into the accumulation grid. lpv_conserve.comp has scaled every
// source cell first, so no step sends out more light than it received.
#include "common.glsl"
#include "lpv_faces.glsl"
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
uniform sampler3D source_r;
uniform sampler3D source_g;
uniform sampler3D source_b;
uniform sampler3D geometry_volume;
layout(rgba32f, binding = 0) uniform writeonly image3D target_r;
layout(rgba32f, binding = 1) uniform writeonly image3D target_g;
layout(rgba32f, binding = 2) uniform writeonly image3D target_b;
layout(rgba32f, binding = 3) uniform image3D sum_r;
layout(rgba32f, binding = 4) uniform image3D sum_g;
layout(rgba32f, binding = 5) uniform image3D sum_b;
uniform int grid_size;
uniform bool use_occlusion;

// Share of light through the face between this cell and the one it came from along -d.
float transmittance(ivec3 cell, vec3 d, vec3 travel) {
    if (!use_occlusion) return 1.0;
    vec3 uvw = (vec3(cell) + 1.0 - 0.5 * d) / float(grid_size + 1);
    return 1.0 - clamp(dot(texture(geometry_volume, uvw), sh_basis(-travel)), 0.0, 1.0);
}

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(cell, ivec3(grid_size)))) return;
    vec4 r = vec4(0.0), g = vec4(0.0), b = vec4(0.0);
    for (int i = 0; i < 6; ++i) {
        ivec3 neighbour = cell - DIRECTIONS[i];
        if (any(lessThan(neighbour, ivec3(0))) || any(greaterThanEqual(neighbour, ivec3(grid_size)))) continue;
        vec4 nr = texelFetch(source_r, neighbour, 0);
        vec4 ng = texelFetch(source_g, neighbour, 0);
        vec4 nb = texelFetch(source_b, neighbour, 0);
        vec3 d = vec3(DIRECTIONS[i]);
        // Far face: straight through, re-emitted toward d.
        vec4 y = sh_basis(d);
        vec4 lobe = cos_lobe(d) * (FAR_FACE_SOLID_ANGLE / PI) * transmittance(cell, d, d);
        r += max(0.0, dot(nr, y)) * lobe;
        g += max(0.0, dot(ng, y)) * lobe;
        b += max(0.0, dot(nb, y)) * lobe;
        // Side faces: evaluated toward (2d + s)/sqrt(5), re-emitted toward s.
        for (int j = 0; j < 6; ++j) {
            vec3 s = vec3(DIRECTIONS[j]);
            if (dot(s, d) != 0.0) continue;
            vec3 e = side_face_direction(d, s);
            vec4 ye = sh_basis(e);
            vec4 side_lobe = cos_lobe(s) * (SIDE_FACE_SOLID_ANGLE / PI) * transmittance(cell, d, e);
            r += max(0.0, dot(nr, ye)) * side_lobe;
            g += max(0.0, dot(ng, ye)) * side_lobe;
            b += max(0.0, dot(nb, ye)) * side_lobe;
        }
    }
    imageStore(target_r, cell, r);
    imageStore(target_g, cell, g);
    imageStore(target_b, cell, b);
    imageStore(sum_r, cell, imageLoad(sum_r, cell) + r);
    imageStore(sum_g, cell, imageLoad(sum_g, cell) + g);
    imageStore(sum_b, cell, imageLoad(sum_b, cell) + b);
}
