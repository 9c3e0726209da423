#version 450 core
// The irradiance of the point emitters at every pixel from the emitter grid's textures
// (emitter_grid_build.comp), read at the pixel's position with INTERPOLATION 0:
// trilinear, 1: tricubic (Catmull-Rom, interpolating and C1, as Lekien & Marsden's
// is), 2: super-sampled (the mean of eight trilinear reads a quarter cell around it,
// the seed's remedy for the staircase of coarse cells, which is one trilinear read of
// the textures made twice as fine for it: emitter_supersample.comp). A surface of normal n gets the
// direction sums' halves facing it weighted by n², as an ambient cube (exact for
// surfaces facing the axes), coloured as the colour sum.
#include "common.glsl"
#include "gbuffer.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform writeonly image2D irradiance;
uniform sampler3D colour_sum;
uniform sampler3D direction_positive;
uniform sampler3D direction_negative;
uniform vec3 grid_origin;
uniform float cell_size;
uniform int grid_size;
uniform vec3 luminance_weights;

// Each read gives the colour sum and the luminance the surface of normal n gets.
vec4 fetch(ivec3 at, vec3 n) {
    vec3 positive = texelFetch(direction_positive, at, 0).xyz, negative = texelFetch(direction_negative, at, 0).xyz;
    return vec4(texelFetch(colour_sum, at, 0).rgb, dot(n * n, mix(negative, positive, step(0.0, n))));
}

vec4 trilinear(vec3 g, vec3 n) {
    vec3 uvw = g / float(grid_size);
    vec3 positive = texture(direction_positive, uvw).xyz, negative = texture(direction_negative, uvw).xyz;
    return vec4(texture(colour_sum, uvw).rgb, dot(n * n, mix(negative, positive, step(0.0, n))));
}

vec4 catmull_rom(float t) {
    float t2 = t * t, t3 = t2 * t;
    return 0.5 * vec4(-t3 + 2.0 * t2 - t, 3.0 * t3 - 5.0 * t2 + 2.0, -3.0 * t3 + 4.0 * t2 + t, t3 - t2);
}

vec4 tricubic(vec3 g, vec3 n) {
    vec3 c = g - 0.5;
    ivec3 base = ivec3(floor(c)) - 1;
    vec3 f = c - floor(c);
    vec4 wx = catmull_rom(f.x), wy = catmull_rom(f.y), wz = catmull_rom(f.z);
    vec4 sum = vec4(0.0);
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                ivec3 at = clamp(base + ivec3(x, y, z), ivec3(0), ivec3(grid_size - 1));
                sum += wx[x] * wy[y] * wz[z] * fetch(at, n);
            }
    return max(sum, vec4(0.0));  // a cubic overshoots below a peak
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(irradiance)))) return;
    vec3 p, n, albedo;
    vec3 light = vec3(0.0);
    if (gbuffer_surface(pixel, p, n, albedo)) {
        vec3 g = (p - grid_origin) / cell_size;
#if INTERPOLATION == 1
        vec4 read = tricubic(g, n);
#else
        vec4 read = trilinear(g, n);  // of the fine textures when super-sampled
#endif
        float total = dot(read.rgb, luminance_weights);
        light = total > 0.0 ? read.rgb * (read.a / total) : vec3(0.0);
    }
    imageStore(irradiance, pixel, vec4(light, 0.0));
}
