#version 450 core
// The G-buffer as floats for the corrections (gpu/corrections.py Guide): per pixel the
// surface's position and whether it is seen, its normal, its albedo; where nothing is seen,
// the ray's direction in place of the position (near to far: perspective or orthographic).
#include "gbuffer.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) writeonly buffer Guide { vec4 guide[]; };

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = textureSize(g_depth, 0);
    if (any(greaterThanEqual(pixel, size))) return;
    int at = 3 * (pixel.y * size.x + pixel.x);
    vec3 p, n, albedo;
    if (gbuffer_surface(pixel, p, n, albedo)) {
        guide[at] = vec4(p, 1.0);
        guide[at + 1] = vec4(n, 0.0);
        guide[at + 2] = vec4(albedo, 0.0);
        return;
    }
    guide[at] = vec4(normalize(gbuffer_unproject(pixel, 1.0) - gbuffer_unproject(pixel, 0.0)), 0.0);
    guide[at + 1] = vec4(0.0);
    guide[at + 2] = vec4(0.0);
}
