#version 450 core
// The surface points the camera sees on a lattice of pixels (gpu/grids.py places the
// grids around them); w = 0 where a pixel sees nothing.
#include "gbuffer.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) writeonly buffer Points { vec4 points[]; };
uniform int lattice;

void main() {
    ivec2 at = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(at, ivec2(lattice)))) return;
    ivec2 size = textureSize(g_depth, 0);
    ivec2 pixel = min((2 * at + 1) * size / (2 * lattice), size - 1);
    vec3 p, n, albedo;
    bool seen = gbuffer_surface(pixel, p, n, albedo);
    points[at.y * lattice + at.x] = seen ? vec4(p, 1.0) : vec4(0.0);
}
