// What a reflective shadow map's texel holds, from the surface there
// (surface_vertices.glsl): rsm.frag's fragments, and rsm_resolve.comp's texels of the
// triangles a compute pass rasterised.
#include "common.glsl"
#include "glossy_word.glsl"
#include "light.glsl"
#include "paraboloid.glsl"
#include "specular.glsl"
#include "surface.glsl"
#include "surface_vertices.glsl"
#define PROJECTION_CUBE 0
#define PROJECTION_PARABOLOID 1
#define PROJECTION_ORTHO 2
uniform vec2 face_origin;        // this face's lower-left texel in the atlas
uniform float resolution;        // texels along one side of a face
uniform float ortho_texel_area;  // sun: the area one texel covers across the beam
uniform int projection_kind;

// The texel at `texel_centre` (in the atlas) of the surface of albedo `surface_albedo`:
// `position` xyz world, w shadow distance (0: empty); `normal` xyz toward the light, w
// surfel area; `flux` rgb reflected flux in W, w the share of it the glossy layer reflects
// and its roughness (glossy_word.glsl; 0 without GLOSSY_LAYER).
void surface_rsm_texel(vec4 surface_albedo, SurfacePoint here, vec2 texel_centre, out vec4 position, out vec4 normal,
                       out vec4 flux) {
    vec3 world_position = surface_vec3(0);
    vec3 w;
    float dist;
    light_ray(world_position, w, dist);
    vec3 n = normalize(surface_vec3(VERTEX_NORMAL));
    if (dot(n, w) > 0.0) n = -n;
    float cos_receiver = max(abs(dot(n, w)), 0.05);
    vec3 power;
    float area;
    if (light_kind == LIGHT_SUN) {
        power = light_peak * ortho_texel_area;
        area = ortho_texel_area / cos_receiver;
    } else {
        // The texel's solid angle from its map coordinates (METHOD §2).
        vec2 uv = (texel_centre - face_origin) / resolution * 2.0 - 1.0;
        float solid_angle = projection_kind == PROJECTION_PARABOLOID
            ? paraboloid_texel_solid_angle(uv, resolution)
            : cube_texel_solid_angle(uv, resolution);
        power = light_intensity(w) * solid_angle;
        area = dist * dist * solid_angle / cos_receiver;
    }
    position = vec4(world_position, max(dist, 1e-30));
    normal = vec4(n, area);
    vec3 colour = surface_colour(surface_albedo, here);
    float word = 0.0;
#ifdef GLOSSY_LAYER
    vec4 specular = surface_vec4(VERTEX_SPECULAR);  // F0 rgb, roughness
    float metallic = surface_float(VERTEX_METALLIC);
    vec3 glossy = specular_albedo(specular.rgb, metallic, specular.a, abs(dot(n, w)));
    colour = diffuse_bounce_colour(colour, specular.rgb, metallic, specular.a) + glossy;
    float total = colour.r + colour.g + colour.b;
    word = glossy_word(total > 0.0 ? (glossy.r + glossy.g + glossy.b) / total : 0.0, specular.a);
#endif
    flux = vec4(colour * power, word);
}
