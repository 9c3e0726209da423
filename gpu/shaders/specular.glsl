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

uniform sampler2D specular_albedo_table;  // gpu/specular_albedo.py texture_rows (linear filtering)

// The table read bilinearly: the lobe's albedo with a Fresnel of 1, and the parts
// Schlick's and a dielectric's rise toward grazing weigh it by.
vec3 specular_albedo_terms(float roughness, float nv) {
    vec2 size = vec2(textureSize(specular_albedo_table, 0));
    vec2 texel = clamp(vec2(nv, roughness), 0.0, 1.0) * (vec2(size.x - 1.0, size.y) - 1.0) + 0.5;
    return texture(specular_albedo_table, texel / size).rgb;
}

// The lobe's terms meaned over directions (the table's last column), for light from all
// around.
vec3 mean_specular_albedo_terms(float roughness) {
    vec2 size = vec2(textureSize(specular_albedo_table, 0));
    return texture(specular_albedo_table, vec2(size.x - 0.5, clamp(roughness, 0.0, 1.0) * (size.y - 1.0) + 0.5) / size).rgb;
}

// A layer's albedo from the lobe's terms: F0 `f0` rising toward grazing as a metal's
// (Schlick) or a dielectric's by the metallic share, what the single-scattering lobe loses
// given back as Cycles' multiple-scattering GGX does (gpu/specular_albedo.py). A layer
// of F0 0 (Specular IOR Level 0) reflects nothing.
vec3 layer_albedo(vec3 f0, float metallic, vec3 terms) {
    float rise = mix(terms.z, terms.y, metallic);
    float f90 = clamp(50.0 * max(f0.r, max(f0.g, f0.b)), 0.0, 1.0);
    vec3 single = f0 * (terms.x - rise) + rise * f90;
    float lost = 1.0 - terms.x;
    vec3 average = f0 + (1.0 - f0) / 21.0;
    return single + single * average * lost / (1.0 - average * lost);
}

// The share of uniform incoming light a glossy layer of F0 `f0`, metallic share and
// Blender's `roughness` reflects toward a viewer at cos `nv` (the split sum's DFG term).
vec3 specular_albedo(vec3 f0, float metallic, float roughness, float nv) {
    return layer_albedo(f0, metallic, specular_albedo_terms(roughness, nv));
}

// The share of the light below a glossy layer of albedo `layer` that the layer lets
// through: one less its largest channel.
float kept_under(vec3 layer) {
    return 1.0 - clamp(max(layer.r, max(layer.g, layer.b)), 0.0, 1.0);
}

// The share of the light below the glossy layer that it keeps from a viewer at cos `nv`:
// Cycles darkens the diffuse under the layer by the layer's albedo toward the viewer, its
// largest channel (closure_layering_weight).
float diffuse_under_layer(vec3 f0, float metallic, float roughness, float nv) {
    return kept_under(specular_albedo(f0, metallic, roughness, nv));
}

// What a surface of diffuse colour `albedo` under a glossy layer sends on as diffuse light:
// the diffuse it keeps seen from every direction (the layer's albedo meaned over them). The
// layer itself reflects specular_albedo of the light arriving at cos nl, along its lobe
// (docs/method.md, "Specular light").
vec3 diffuse_bounce_colour(vec3 albedo, vec3 f0, float metallic, float roughness) {
    return albedo * kept_under(layer_albedo(f0, metallic, mean_specular_albedo_terms(roughness)));
}
