#version 450 core
// Reference DPM (thesis §6): every paraboloid texel takes its exact direction from the
// inverse projection and fetches the cube map there, flux rescaled from the cube texel's
// solid angle to the paraboloid texel's.
#include "common.glsl"
#include "rsm_lookup.glsl"
#include "rsm_texel.glsl"
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

void main() {
    ivec2 local = ivec2(gl_GlobalInvocationID.xy);
    if (local.x >= resolution || local.y >= resolution) return;
    vec2 st = (vec2(local) + 0.5) / float(resolution) * 2.0 - 1.0;
    vec4 position = vec4(0.0), normal = vec4(0.0), flux = vec4(0.0);
    if (dot(st, st) <= 1.0) {
        vec3 direction = transpose(mat3(hemisphere_view)) * paraboloid_direction(st);
        int face;
        ivec2 texel;
        if (rsm_face_texel(light_position + direction, face, texel)) {
            vec2 centre = (vec2(texel) + 0.5) / float(lookup_resolution) * 2.0 - 1.0;
            float ratio = paraboloid_texel_solid_angle(st, float(resolution)) /
                          cube_texel_solid_angle(centre, float(lookup_resolution));
            copy_rsm_texel(cube_position, cube_normal, cube_flux, texel + lookup_origin[face], ratio,
                           position, normal, flux);
        }
    }
    ivec2 target = face_origin + local;
    imageStore(target_position, target, position);
    imageStore(target_normal, target, normal);
    imageStore(target_flux, target, flux);
}
