// The glossy reflection of the Principled BSDF (docs/method.md, "Specular light"): GGX
// with the height-correlated Smith visibility and Schlick's Fresnel from F0. Needs
// common.glsl (PI).

const float MIN_SPECULAR_ALPHA = 0.002;  // a mirror's lobe: keeps a lamp of no size a (tiny) highlight

// GGX's alpha from Blender's roughness (squared, as Cycles does), widened by a light's
// angular radius `spread` (its tangent): a sized light's highlight.
float specular_alpha(float roughness, float spread) {
    return clamp(roughness * roughness + 0.5 * spread, MIN_SPECULAR_ALPHA, 1.0);
}

vec3 schlick_fresnel(vec3 f0, float cos_theta) {
    float m = clamp(1.0 - cos_theta, 0.0, 1.0);
    float m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// The glossy BRDF (1/sr) for the normal `n`, the unit directions toward the viewer `v`
// and toward the light `l`, F0 `f0` and GGX alpha `alpha`; 0 below the surface.
vec3 ggx_brdf(vec3 n, vec3 v, vec3 l, vec3 f0, float alpha) {
    float nl = dot(n, l);
    float nv = max(dot(n, v), 1e-4);
    if (nl <= 0.0) return vec3(0.0);
    vec3 h = normalize(v + l);
    float nh = max(dot(n, h), 0.0);
    float a2 = alpha * alpha;
    float d = nh * nh * (a2 - 1.0) + 1.0;
    float distribution = a2 / (PI * d * d);
    float visibility = 0.5 / (nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2));
    return distribution * visibility * schlick_fresnel(f0, max(dot(v, h), 0.0));
}
