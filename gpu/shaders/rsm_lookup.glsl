// Where a world point falls in a light's RSM atlas: the face that sees it and its texel.
// Uniforms come from ReflectiveShadowMap.lookup_uniforms() in gpu/rsm.py.
#include "paraboloid.glsl"
uniform mat4 lookup_matrix[6];    // view-projection, or world-to-hemisphere for paraboloids
uniform ivec2 lookup_origin[6];   // each face's lower-left texel in the atlas
uniform int lookup_faces;
uniform int lookup_resolution;
uniform bool lookup_paraboloid;

// The first face that sees p, and p's texel within that face.
bool rsm_face_texel(vec3 p, out int face, out ivec2 texel) {
    for (int f = 0; f < lookup_faces; ++f) {
        vec2 ndc;
        if (lookup_paraboloid) {
            vec3 h = (lookup_matrix[f] * vec4(p, 1.0)).xyz;
            if (h.z < 0.0) continue;
            ndc = paraboloid_project(h);
        } else {
            vec4 clip = lookup_matrix[f] * vec4(p, 1.0);
            if (clip.w <= 0.0) continue;
            ndc = clip.xy / clip.w;
            if (any(greaterThan(abs(ndc), vec2(1.0)))) continue;
        }
        face = f;
        texel = clamp(ivec2(floor((ndc * 0.5 + 0.5) * float(lookup_resolution))), ivec2(0),
                      ivec2(lookup_resolution - 1));
        return true;
    }
    return false;
}
