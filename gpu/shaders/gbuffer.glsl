// The camera G-buffer of shaders/gbuffer.frag: a depth texture and one packed surface
// texel per pixel (octahedral normal in two 16-bit snorms, albedo as three floats);
// positions are rebuilt from the depth. A second texture, g_specular (RGBA16UI), holds the
// glossy reflection for the passes that shade it (gbuffer_specular): F0 rgb in 16-bit
// unorms, roughness and metallic in 8 bits each.
uniform sampler2D g_depth;
uniform usampler2D g_surface;
uniform mat4 inverse_view_projection;
uniform usampler2D g_specular;

vec2 octahedral_encode(vec3 n) {
    n /= abs(n.x) + abs(n.y) + abs(n.z);
    vec2 e = n.xy;
    if (n.z < 0.0) e = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return e;
}

vec3 octahedral_decode(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

uvec4 gbuffer_pack(vec3 normal, vec3 albedo) {
    return uvec4(packSnorm2x16(octahedral_encode(normal)), floatBitsToUint(albedo));
}

// The world point at the centre of `pixel` and the window depth `depth` (0 near, 1 far).
vec3 gbuffer_unproject(ivec2 pixel, float depth) {
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(textureSize(g_depth, 0)) * 2.0 - 1.0;
    vec4 world = inverse_view_projection * vec4(ndc, depth * 2.0 - 1.0, 1.0);
    return world.xyz / world.w;
}

// The surface the camera sees at `pixel`; false where it sees nothing.
bool gbuffer_surface(ivec2 pixel, out vec3 position, out vec3 normal, out vec3 albedo) {
    float depth = texelFetch(g_depth, pixel, 0).r;
    if (depth >= 1.0) return false;
    position = gbuffer_unproject(pixel, depth);
    uvec4 surface = texelFetch(g_surface, pixel, 0);
    normal = octahedral_decode(unpackSnorm2x16(surface.x));
    albedo = uintBitsToFloat(surface.yzw);
    return true;
}

uvec4 gbuffer_pack_specular(vec3 f0, float roughness, float metallic) {
    uvec3 f = uvec3(round(clamp(f0, 0.0, 1.0) * 65535.0));
    uvec2 rm = uvec2(round(clamp(vec2(roughness, metallic), 0.0, 1.0) * 255.0));
    return uvec4(f, (rm.x << 8) | rm.y);
}

// The glossy reflection at `pixel`: F0 (rgb) and Blender's roughness (a); its metallic share.
vec4 gbuffer_specular(ivec2 pixel, out float metallic) {
    uvec4 t = texelFetch(g_specular, pixel, 0);
    metallic = float(t.a & 255u) / 255.0;
    return vec4(vec3(t.rgb) / 65535.0, float(t.a >> 8) / 255.0);
}

// The unit direction from the surface point `position` seen at `pixel` toward the camera
// (perspective or orthographic alike: back along the pixel's ray, to the near plane).
vec3 gbuffer_view(ivec2 pixel, vec3 position) {
    return normalize(gbuffer_unproject(pixel, 0.0) - position);
}
