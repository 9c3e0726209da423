// A surface's diffuse colour and what of it lets light through (mesh_buffer.py,
// surface_images.py, docs/method.md "Alpha and transmission"). `albedo` is the vertex
// albedo and alpha, `coord` the surface coordinate (u, v, image layer, alpha image layer;
// layer -1: none), `transmission` the tint and the share transmitted of what is not cut out.
uniform sampler2DArray surface_images;
uniform uint cut_out_pattern;  // the VPL pattern: hashed cut-outs differ from one pattern to the next

// The colour of the surface's image at `coord` (1 where it has none).
vec3 surface_image(vec4 coord) {
    if (coord.z < -0.5) return vec3(1.0);
    return texture(surface_images, vec3(coord.xy, floor(coord.z + 0.5))).rgb;
}

vec3 surface_colour(vec4 albedo, vec4 coord) {
    return albedo.rgb * surface_image(coord);
}

// What of the light meeting the surface is not cut out: alpha times its image's alpha.
float surface_alpha(vec4 albedo, vec4 coord) {
    if (coord.w < -0.5) return albedo.a;
    return albedo.a * texture(surface_images, vec3(coord.xy, floor(coord.w + 0.5))).a;
}

uint cut_out_hash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// The hashed cut-out's threshold in (0, 1): fixed per pixel (or map texel) and pattern.
float cut_out_threshold(vec2 frag_coord) {
    uvec2 p = uvec2(frag_coord);
    uint h = cut_out_hash(p.x ^ cut_out_hash(p.y ^ cut_out_hash(cut_out_pattern + 0x9e3779b9u)));
    return (float(h >> 8) + 0.5) / 16777216.0;
}

// Whether the surface is opaque at this pixel: its opaque share, alpha times what it
// does not transmit, against the hashed threshold (1 always, 0 never).
bool surface_covers(vec4 albedo, vec4 coord, vec4 transmission, vec2 frag_coord) {
    return surface_alpha(albedo, coord) * (1.0 - transmission.w) > cut_out_threshold(frag_coord);
}

// Where the surface does not cover the pixel, what multiplies the light passing it: the
// cut-out part untinted, the transmitted part tinted, as shares of what passes. False
// where it covers the pixel or passes everything untouched.
bool surface_passing_tint(vec4 albedo, vec4 coord, vec4 transmission, vec2 frag_coord, out vec3 tint) {
    float alpha = surface_alpha(albedo, coord);
    float opaque = alpha * (1.0 - transmission.w);
    if (opaque > cut_out_threshold(frag_coord) || transmission.w <= 0.0) return false;
    tint = ((1.0 - alpha) + alpha * transmission.w * transmission.rgb) / max(1.0 - opaque, 1e-6);
    return any(lessThan(tint, vec3(1.0)));
}
