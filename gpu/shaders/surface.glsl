// A surface's diffuse colour and what of it lets light through (mesh_buffer.py,
// surface_images.py, docs/method.md "Alpha and transmission"). `albedo` is the vertex
// albedo and alpha, a SurfacePoint where its images are read, `transmission` the tint and
// the share transmitted of what is not cut out.
#include "hash.glsl"
uniform sampler2DArray surface_images;
uniform uint cut_out_pattern;  // the VPL pattern: hashed cut-outs differ from one pattern to the next

// The surface coordinate (u, v, image layer, alpha image layer; layer -1: none) and its
// change a pixel along x and along y: the footprint its images are filtered over.
struct SurfacePoint {
    vec4 coord;
    vec2 along_x;
    vec2 along_y;
};

#ifdef TEXEL_FILTER
// Level `level` of image `layer` at `uv`, bilinear, repeating.
vec4 surface_bilinear(vec2 uv, int layer, int level) {
    ivec2 size = textureSize(surface_images, level).xy;
    vec2 at = uv * vec2(size) - 0.5;
    ivec2 low = ivec2(floor(at));
    vec2 f = at - vec2(low);
    ivec2 x = (ivec2(low.x, low.x + 1) % size.x + size.x) % size.x;
    ivec2 y = (ivec2(low.y, low.y + 1) % size.y + size.y) % size.y;
    return mix(mix(texelFetch(surface_images, ivec3(x.x, y.x, layer), level),
                   texelFetch(surface_images, ivec3(x.y, y.x, layer), level), f.x),
               mix(texelFetch(surface_images, ivec3(x.x, y.y, layer), level),
                   texelFetch(surface_images, ivec3(x.y, y.y, layer), level), f.x), f.y);
}

// The image's colour at `s`, filtered over its footprint. With TEXEL_FILTER (llvmpipe,
// gpu/context.py) trilinear between the two levels GL's isotropic rule picks, fetched
// texel by texel: llvmpipe's sampler works out a level per pixel quad from its four
// coordinates even when told the level or the gradients, and its helper invocations read
// nothing from storage buffers, so a quad that crosses a triangle's edge sampled a
// blurred level.
vec4 surface_texel(SurfacePoint s, float layer) {
    vec2 texels = vec2(textureSize(surface_images, 0).xy);
    float top = float(textureQueryLevels(surface_images) - 1);
    float level = clamp(log2(max(max(length(s.along_x * texels), length(s.along_y * texels)), 1e-30)), 0.0, top);
    int below = int(level), image = int(floor(layer + 0.5));
    return mix(surface_bilinear(s.coord.xy, image, below), surface_bilinear(s.coord.xy, image, min(below + 1, int(top))),
               level - float(below));
}
#else
vec4 surface_texel(SurfacePoint s, float layer) {
    return textureGrad(surface_images, vec3(s.coord.xy, floor(layer + 0.5)), s.along_x, s.along_y);
}
#endif

// The colour of the surface's image at `s` (1 where it has none).
vec3 surface_image(SurfacePoint s) {
    if (s.coord.z < -0.5) return vec3(1.0);
    return surface_texel(s, s.coord.z).rgb;
}

vec3 surface_colour(vec4 albedo, SurfacePoint s) {
    return albedo.rgb * surface_image(s);
}

// What of the light meeting the surface is not cut out: alpha times its image's alpha.
float surface_alpha(vec4 albedo, SurfacePoint s) {
    if (s.coord.w < -0.5) return albedo.a;
    return albedo.a * surface_texel(s, s.coord.w).a;
}

// The hashed cut-out's threshold in (0, 1): fixed per pixel (or map texel) and pattern.
float cut_out_threshold(vec2 frag_coord) {
    uvec2 p = uvec2(frag_coord);
    uint h = hash32(p.x ^ hash32(p.y ^ hash32(cut_out_pattern + 0x9e3779b9u)));
    return (float(h >> 8) + 0.5) / 16777216.0;
}

// Whether the surface is opaque at this pixel: its opaque share, alpha times what it
// does not transmit, against the hashed threshold (1 always, 0 never).
bool surface_covers(vec4 albedo, SurfacePoint s, vec4 transmission, vec2 frag_coord) {
    return surface_alpha(albedo, s) * (1.0 - transmission.w) > cut_out_threshold(frag_coord);
}

// Where the surface does not cover the pixel, what multiplies the light passing it: the
// cut-out part untinted, the transmitted part tinted, as shares of what passes. False
// where it covers the pixel or passes everything untouched.
bool surface_passing_tint(vec4 albedo, SurfacePoint s, vec4 transmission, vec2 frag_coord, out vec3 tint) {
    float alpha = surface_alpha(albedo, s);
    float opaque = alpha * (1.0 - transmission.w);
    if (opaque > cut_out_threshold(frag_coord) || transmission.w <= 0.0) return false;
    tint = ((1.0 - alpha) + alpha * transmission.w * transmission.rgb) / max(1.0 - opaque, 1e-6);
    return any(lessThan(tint, vec3(1.0)));
}
