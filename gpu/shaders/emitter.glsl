// A point emitter (gpu/light_grid.py): a VPL, or a cluster of them. position.w > 0: valid;
// normal.xyz: the unit normal of a cosine emitter, zero for one that emits alike in every
// direction; normal.w: the area it stands for; flux.rgb: its flux (W).
struct Emitter { vec4 position; vec4 normal; vec4 flux; };

// Irradiance an emitter gives a surface at distance vector d from it, facing it: its
// radiant intensity toward d over r^2, with r^2 grown by `singularity_bound` times the
// area over pi: at 1 as a disk of that area gives on its axis (pi L R^2 / (r^2 + R^2)),
// so it stays finite next to it (settings.py singularity_bound; its bias: docs/accuracy.md).
uniform float singularity_bound;
vec3 emitter_light(Emitter e, vec3 d) {
    float r2 = dot(d, d);
    vec3 w = d * inversesqrt(max(r2, 1e-30));
    bool cosine = dot(e.normal.xyz, e.normal.xyz) > 0.5;
    float intensity = cosine ? max(0.0, dot(e.normal.xyz, w)) / PI : 0.25 / PI;
    return e.flux.rgb * intensity / (r2 + singularity_bound * e.normal.w / PI + 1e-30);
}
