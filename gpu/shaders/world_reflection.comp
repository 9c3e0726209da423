#version 450 core
// Adds the world's light a glossy surface reflects toward the camera into the direct image
// (Cycles' Glossy Direct holds it too): the world's lighting map along the reflected view
// ray, read from its mip chain at a level whose texels are about as wide as the GGX lobe
// (alpha radians), times the split sum's DFG term (specular.glsl). Not shadowed: the
// scene does not occlude it (docs/method.md, "Specular light").
#include "common.glsl"
#include "gbuffer.glsl"
#include "specular.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform image2D direct;
uniform sampler2D world_reflection;  // equirectangular, as Blender's Environment Texture maps it
uniform int reflection_levels;       // its mip chain's last level

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(direct)))) return;
    vec3 p, n, albedo;
    if (!gbuffer_surface(pixel, p, n, albedo)) return;
    float metallic;
    vec4 gloss = gbuffer_specular(pixel, metallic);
    if (!any(greaterThan(gloss.rgb, vec3(0.0)))) return;
    vec3 v = gbuffer_view(pixel, p);
    vec3 r = reflect(-v, n);
    float alpha = specular_alpha(gloss.a, 0.0);
    float width = float(textureSize(world_reflection, 0).x);
    float level = clamp(log2(max(alpha * width / PI, 1.0)), 0.0, float(reflection_levels));
    vec2 uv = vec2(0.5 - atan(r.y, r.x) / (2.0 * PI), 1.0 - acos(clamp(r.z, -1.0, 1.0)) / PI);
    vec3 radiance = textureLod(world_reflection, uv, level).rgb;
    vec4 before = imageLoad(direct, pixel);
    imageStore(direct, pixel, before + vec4(radiance * environment_dfg(gloss.rgb, gloss.a, max(dot(n, v), 1e-4)), 0.0));
}
