#version 450 core
// Reference DPM (thesis §6): every paraboloid texel takes its exact direction from the
// inverse projection and fetches the cube map there, flux rescaled from the cube texel's
// solid angle to the paraboloid texel's.
#include "paraboloid.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
uniform sampler2D cube_position;
uniform sampler2D cube_normal;
uniform sampler2D cube_flux;
layout(rgba32f, binding = 0) uniform writeonly image2D target_position;
layout(rgba32f, binding = 1) uniform writeonly image2D target_normal;
layout(rgba32f, binding = 2) uniform writeonly image2D target_flux;
uniform mat4 hemisphere_view;
uniform ivec2 face_origin;
uniform int resolution;
uniform vec3 light_position;
uniform mat4 cube_matrix[6];
uniform ivec2 cube_origin[6];
uniform int cube_faces;
uniform int cube_resolution;

void main() {
    ivec2 local = ivec2(gl_GlobalInvocationID.xy);
    if (local.x >= resolution || local.y >= resolution) return;
    vec2 st = (vec2(local) + 0.5) / float(resolution) * 2.0 - 1.0;
    vec4 position = vec4(0.0), normal = vec4(0.0), flux = vec4(0.0);
    if (dot(st, st) <= 1.0) {
        vec3 direction = transpose(mat3(hemisphere_view)) * paraboloid_direction(st);
        for (int f = 0; f < cube_faces; ++f) {
            vec4 clip = cube_matrix[f] * vec4(light_position + direction, 1.0);
            if (clip.w <= 0.0) continue;
            vec2 uv = clip.xy / clip.w;
            if (any(greaterThan(abs(uv), vec2(1.0)))) continue;
            ivec2 texel = clamp(ivec2(floor((uv * 0.5 + 0.5) * float(cube_resolution))), ivec2(0),
                                ivec2(cube_resolution - 1));
            vec2 centre = (vec2(texel) + 0.5) / float(cube_resolution) * 2.0 - 1.0;
            float cube_solid_angle = 4.0 / float(cube_resolution * cube_resolution) / pow(1.0 + dot(centre, centre), 1.5);
            float ratio = paraboloid_texel_solid_angle(st, float(resolution)) / cube_solid_angle;
            texel += cube_origin[f];
            position = texelFetch(cube_position, texel, 0);
            normal = texelFetch(cube_normal, texel, 0);
            flux = texelFetch(cube_flux, texel, 0);
            normal.w *= ratio;
            flux.rgb *= ratio;
            break;
        }
    }
    ivec2 target = face_origin + local;
    imageStore(target_position, target, position);
    imageStore(target_normal, target, normal);
    imageStore(target_flux, target, flux);
}
