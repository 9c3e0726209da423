// A point emitter (gpu/light_grid.py): a VPL, or a cluster of them. position.w > 0: valid;
// normal.xyz: the unit normal of a cosine emitter, zero for one that emits alike in every
// direction; normal.w: the area it stands for; flux.rgb: its flux (W).
struct Emitter { vec4 position; vec4 normal; vec4 flux; };

// Irradiance an emitter gives a surface at distance vector d from it, facing it: its
// radiant intensity toward d over r^2, r^2 grown by `singularity_bound` times the area
// over pi: at 1 as a disk of that area gives on its axis (pi L R^2 / (r^2 + R^2)), so it
// stays finite next to it. The pixel gather's converging frames shrink that bound set by
// set, so its bias tends to zero (settings.py singularity_bound; docs/accuracy.md).
uniform float singularity_bound;
float emitter_intensity(Emitter e, vec3 d, float r2) {
    vec3 w = d * inversesqrt(max(r2, 1e-30));
    bool cosine = dot(e.normal.xyz, e.normal.xyz) > 0.5;
    return cosine ? max(0.0, dot(e.normal.xyz, w)) / PI : 0.25 / PI;
}

vec3 emitter_light(Emitter e, vec3 d) {
    float r2 = dot(d, d);
    return e.flux.rgb * emitter_intensity(e, d, r2) / (r2 + singularity_bound * e.normal.w / PI + 1e-30);
}

// The same with r^2 held at least at `bound` times the area over pi: within the radius R of
// a disk of that area the exitance the disk gives at its centre, beyond R exact. The points
// the emitters' bounce and the later bounces light stand for large areas and their bound
// never shrinks: grown, it took a fifth of their light at 2R and a tenth at 3R; held, it
// takes little (docs/method.md, "The 1/r² bound").
vec3 held_emitter_light(Emitter e, vec3 d, float bound) {
    float r2 = dot(d, d);
    return e.flux.rgb * emitter_intensity(e, d, r2) / (max(r2, bound * e.normal.w / PI) + 1e-30);
}

// The share of an emitter's flux whose bound is held (flux.w): 1 for a point the emitters'
// bounce or a later bounce lit (emitter_bounce.comp), a light grid cluster's flux-weighted
// share of such points (emitter_cluster.comp), 0 for the lights' VPLs and the rest.
float held_share(Emitter e) { return clamp(e.flux.w, 0.0, 1.0); }

// The irradiance of an emitter whose held share of flux holds r^2 at `held` times the area
// over pi and whose rest grows r^2 by `grown` times it.
vec3 shared_emitter_light(Emitter e, vec3 d, float grown, float held) {
    float r2 = dot(d, d);
    float area = e.normal.w / PI, share = held_share(e);
    return e.flux.rgb * emitter_intensity(e, d, r2)
           * ((1.0 - share) / (r2 + grown * area + 1e-30) + share / (max(r2, held * area) + 1e-30));
}
