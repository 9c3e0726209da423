// A point emitter (gpu/light_grid.py): a VPL, or a cluster of them. position.w > 0: valid;
// normal.xyz: the unit normal of a cosine emitter, zero for one that emits alike in every
// direction; normal.w: the area it stands for; flux.rgb: its flux (W).
struct Emitter { vec4 position; vec4 normal; vec4 flux; };

// Irradiance an emitter gives a surface at distance vector d from it, facing it: its
// radiant intensity toward d over r^2, bounded next to it by the area A it stands for,
// in one of two ways (docs/method.md, "The 1/r² bound"). Its share 1 - h grows r^2 by
// `grown` A/pi, as a disk of area A gives on its axis (pi L R^2 / (r^2 + R^2)): the pixel
// gather's converging frames shrink that bound set by set, so its bias tends to zero. Its
// share h holds r^2 at least at `held` A/pi: within the disk's radius R the exitance the
// disk gives at its centre, beyond R exact, which takes little light where the bound never
// shrinks (growing it took a fifth of the light at 2R and a tenth at 3R).
uniform float singularity_bound;
vec3 bounded_emitter_light(Emitter e, vec3 d, float grown, float held, float h) {
    float r2 = dot(d, d);
    vec3 w = d * inversesqrt(max(r2, 1e-30));
    bool cosine = dot(e.normal.xyz, e.normal.xyz) > 0.5;
    float intensity = cosine ? max(0.0, dot(e.normal.xyz, w)) / PI : 0.25 / PI;
    float area = e.normal.w / PI;
    return e.flux.rgb * intensity * ((1.0 - h) / (r2 + grown * area + 1e-30) + h / (max(r2, held * area) + 1e-30));
}

// The share of an emitter's flux whose bound is held (flux.w): 1 for a point the emitters'
// bounce or a later bounce lit (emitter_bounce.comp), a light grid cluster's flux-weighted
// share of such points (emitter_cluster.comp), 0 for the lights' VPLs and the rest.
float held_share(Emitter e) { return clamp(e.flux.w, 0.0, 1.0); }

// With `singularity_bound` grown for all of its flux (settings.py singularity_bound).
vec3 emitter_light(Emitter e, vec3 d) { return bounded_emitter_light(e, d, singularity_bound, 0.0, 0.0); }

// With its held share held at `held`, the rest grown by `grown`.
vec3 shared_emitter_light(Emitter e, vec3 d, float grown, float held) {
    return bounded_emitter_light(e, d, grown, held, held_share(e));
}
