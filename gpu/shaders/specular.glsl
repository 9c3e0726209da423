// The glossy reflection of the Principled BSDF (docs/method.md, "Specular light"): GGX
// with the height-correlated Smith visibility and, as Cycles does, a dielectric's Fresnel
// (of the IOR whose F0 it is, tinted) and a metal's Schlick Fresnel from F0, mixed by the
// metallic share. Needs common.glsl (PI).

const float MIN_SPECULAR_ALPHA = 0.002;  // a mirror's lobe: keeps a lamp of no size a (tiny) highlight

// GGX's alpha from Blender's roughness (squared, as Cycles does), widened by a light's
// angular radius `spread` (its tangent): a sized light's highlight.
float specular_alpha(float roughness, float spread) {
    return clamp(roughness * roughness + 0.5 * spread, MIN_SPECULAR_ALPHA, 1.0);
}

// The unpolarised Fresnel reflectance of a dielectric of relative IOR `eta` (Cycles'
// fresnel_dielectric_cos).
float dielectric_fresnel(float c, float eta) {
    float g = eta * eta - 1.0 + c * c;
    if (g <= 0.0) return 1.0;
    g = sqrt(g);
    float a = (g - c) / (g + c);
    float b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return 0.5 * a * a * (1.0 + b * b);
}

// F0 + (1 - F0) s: s the dielectric's rise from its own F0 toward 1 (its IOR from the
// largest F0 channel) and Schlick's (1 - cos)^5, mixed by `metallic`.
vec3 principled_fresnel(vec3 f0, float metallic, float cos_theta) {
    float c = clamp(cos_theta, 0.0, 1.0);
    float m = 1.0 - c;
    float schlick = m * m * m * m * m;
    float f = clamp(max(f0.r, max(f0.g, f0.b)), 1e-4, 0.99);
    float root = sqrt(f);
    float dielectric = (dielectric_fresnel(c, (1.0 + root) / (1.0 - root)) - f) / (1.0 - f);
    return f0 + (1.0 - f0) * mix(dielectric, schlick, metallic);
}

// The glossy BRDF (1/sr) for the normal `n`, the unit directions toward the viewer `v`
// and toward the light `l`, F0 `f0`, the metallic share and GGX alpha `alpha`; 0 below
// the surface.
vec3 ggx_brdf(vec3 n, vec3 v, vec3 l, vec3 f0, float metallic, float alpha) {
    float nl = dot(n, l);
    float nv = max(dot(n, v), 1e-4);
    if (nl <= 0.0) return vec3(0.0);
    vec3 h = normalize(v + l);
    float nh = max(dot(n, h), 0.0);
    float a2 = alpha * alpha;
    float d = nh * nh * (a2 - 1.0) + 1.0;
    float distribution = a2 / (PI * d * d);
    float visibility = 0.5 / (nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2));
    return distribution * visibility * principled_fresnel(f0, metallic, max(dot(v, h), 0.0));
}

// The split sum's DFG term: the share of uniform incoming light a glossy surface of F0
// `f0` and Blender's `roughness` reflects toward a viewer at cos `nv` (Karis' analytic fit
// of the GGX / Schlick integral, "Physically Based Shading on Mobile", 2014).
vec3 environment_dfg(vec3 f0, float roughness, float nv) {
    const vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022);
    const vec4 c1 = vec4(1.0, 0.0425, 1.04, -0.04);
    vec4 r = roughness * c0 + c1;
    float a004 = min(r.x * r.x, exp2(-9.28 * nv)) * r.x + r.y;
    vec2 ab = vec2(-1.04, 1.04) * a004 + r.zw;
    return f0 * ab.x + ab.y;
}
