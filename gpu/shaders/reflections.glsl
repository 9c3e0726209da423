// The light glossy surfaces reflect of their surroundings (docs/method.md, "Reflections"):
// one ray a pixel and VPL set (the mirror direction in the first set, then drawn from the
// GGX lobe around it, so a converging frame averages the lobe), traced
// through the G-buffer's depth (a screen-space trace); where it hits a surface that
// surface's direct, indirect and emitted light is reflected. Where it leaves the screen,
// the ray is marched through the occupancy: when it escapes, the world's lighting map is
// reflected along the mirror direction at the level of the lobe's width; when something
// blocks it, the indirect light the grids hold around the ray's direction. Rough lobes
// trust the screen less and the prefiltered lookups more. Times the split sum's DFG term.
// Needs common.glsl, gbuffer.glsl, specular.glsl, the method's lookup and, with
// MARCH_ESCAPE, levels_march.glsl.
#include "hash.glsl"
uniform mat4 view_projection;
uniform vec4 view_z_row;             // the view matrix's third row: a point's view-space z
uniform vec4 projection_z;           // the projection's (2,2), (2,3), (3,2), (3,3): view z from a window depth
uniform int reflection_pattern;      // the VPL pattern: each set draws other rays
uniform float trace_length;          // world units a ray is traced: the scene's diagonal
uniform bool reflect_world;
uniform sampler2D world_reflection;  // equirectangular, as Blender's Environment Texture maps it
uniform int reflection_levels;       // its mip chain's last level
const int TRACE_STEPS = 32;          // samples along a ray, closer together near its start
const int REFINE_STEPS = 5;          // bisections of the step that passed behind a surface
const float TRACE_THICKNESS = 0.03;  // a surface's assumed thickness behind its depth, per unit distance
const float MARCH_CLEARANCE = 1.5;   // finest voxels the ray rises off its surface before the march looks
const vec2 SCREEN_ALPHA = vec2(0.12, 0.35);  // GGX alpha over which the screen's share falls from 1 to 0
const float SCREEN_EDGE = 0.1;       // share of the screen's half-width over which a hit fades out

// A direction drawn from the GGX distribution of visible-ish normals around `n` (alpha
// `alpha`) reflecting the view direction `v`; the mirror direction where it would go below.
vec3 lobe_direction(vec3 n, vec3 v, float alpha, vec2 u) {
    vec3 r = reflect(-v, n);
    float tan2 = alpha * alpha * u.x / max(1.0 - u.x, 1e-6);
    float cos_theta = inversesqrt(1.0 + tan2), sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    vec3 t = normalize(abs(n.z) < 0.999 ? cross(n, vec3(0.0, 0.0, 1.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
    vec3 b = cross(n, t);
    float phi = 2.0 * PI * u.y;
    vec3 h = normalize(t * (sin_theta * cos(phi)) + b * (sin_theta * sin(phi)) + n * cos_theta);
    vec3 d = reflect(-v, h);
    return dot(d, n) > 0.0 ? d : r;
}

// The distance in front of the camera of the surface at window depth `depth` (the
// projection solved for view z: perspective or orthographic alike).
float window_distance(float depth) {
    float ndc = depth * 2.0 - 1.0;
    return -(projection_z.y - ndc * projection_z.w) / (ndc * projection_z.z - projection_z.x);
}

// The pixel the world point `q` falls in; false off the screen or behind the camera.
bool screen_pixel(vec3 q, out ivec2 pixel, out float edge) {
    vec4 clip = view_projection * vec4(q, 1.0);
    if (clip.w <= 0.0) return false;
    vec2 ndc = clip.xy / clip.w;
    edge = 1.0 - max(abs(ndc.x), abs(ndc.y));
    if (edge <= 0.0) return false;
    pixel = ivec2((ndc * 0.5 + 0.5) * vec2(textureSize(g_depth, 0)));
    return true;
}

// Whether the ray from `p` along `d` passes behind the surface the camera sees at the
// pixel of the point t along it, crossing it since the point `before` along it or within
// the assumed thickness behind it, and meets it from its front; that pixel. Behind a
// surface it leaves (an object's far side, which the screen does not show) the ray goes on.
bool behind_surface(vec3 p, vec3 d, float before, float t, out ivec2 pixel, out float edge, out bool off_screen) {
    vec3 q = p + d * t;
    off_screen = !screen_pixel(q, pixel, edge);
    if (off_screen) return false;
    float depth = texelFetch(g_depth, pixel, 0).r;
    if (depth >= 1.0) return false;
    if (dot(octahedral_decode(unpackSnorm2x16(texelFetch(g_surface, pixel, 0).x)), d) >= 0.0) return false;
    float surface = window_distance(depth);
    float sample_depth = -dot(view_z_row, vec4(q, 1.0));
    float before_depth = -dot(view_z_row, vec4(p + d * before, 1.0));
    return sample_depth > surface && (before_depth <= surface || sample_depth - surface < TRACE_THICKNESS * max(surface, 1e-6));
}

// The pixel a ray from `p` along `d` first passes behind a surface at, with its fade toward
// the screen's edges; false where it leaves the screen or reaches `trace_length` first.
bool screen_trace(vec3 p, vec3 d, float jitter, out ivec2 hit, out float fade) {
    float previous = 0.0;
    bool off_screen;
    for (int i = 1; i <= TRACE_STEPS; ++i) {
        float s = (float(i) - 1.0 + jitter) / float(TRACE_STEPS);
        float t = trace_length * s * s;
        if (behind_surface(p, d, previous, t, hit, fade, off_screen)) {
            float low = previous, high = t;
            for (int k = 0; k < REFINE_STEPS; ++k) {
                float middle = 0.5 * (low + high);
                ivec2 pixel;
                float edge;
                if (behind_surface(p, d, low, middle, pixel, edge, off_screen)) { high = middle; hit = pixel; fade = edge; }
                else low = middle;
            }
            fade = clamp(fade / SCREEN_EDGE, 0.0, 1.0);
            return true;
        }
        if (off_screen) return false;
        previous = t;
    }
    return false;
}

// A pixel's reflection before the grids are looked up: `light` is what needs no lookup;
// the pixel's own irradiance adds times `own`, and the hit's (when `seen`, at `pixel`,
// `point` and `normal`) times `weight`. The grids are looked up in one place of the shader
// (shade_indirect.comp main): on llvmpipe a light grid lookup inlined at more places
// broke the G-buffer's reads.
struct Reflection {
    vec3 light;
    vec3 own;
    bool seen;
    ivec2 pixel;
    vec3 point;
    vec3 normal;
    vec3 weight;
};

// Add `share` of the light leaving the surface the camera sees at `pixel` (its direct
// light, glow and, through a lookup, diffuse indirect light): what a reflected ray that
// hits it brings back.
void add_seen(inout Reflection reflection, ivec2 pixel, float share) {
    vec3 q, m, albedo;
    if (!gbuffer_surface(pixel, q, m, albedo)) return;
    vec3 light = imageLoad(direct, pixel).rgb;
    if (add_glow) light += imageLoad(glow, pixel).rgb;
    reflection.light += share * light;
    reflection.seen = true;
    reflection.pixel = pixel;
    reflection.point = q;
    reflection.normal = m;
    reflection.weight = share * albedo / PI * intensity;
}

// Add `share` of the light around the direction `d` from `p` where the screen does not
// show it: the world's (prefiltered for GGX alpha `alpha` along the mirror direction `r`)
// where the ray escapes, else the indirect light the pixel's own lookup found (the
// surroundings' mean radiance above the surface, E / π: a lookup along d costs a second
// one).
void add_surroundings(inout Reflection reflection, ivec2 pixel, vec3 p, vec3 n, vec3 r, vec3 d, float alpha,
                      float share) {
    bool escapes = reflect_world;
#ifdef MARCH_ESCAPE
    if (escapes) {  // marched from where the ray has left its own surface's voxels (a grazing ray far along)
        float voxel = level_voxels[0];
        float rise = MARCH_CLEARANCE * voxel / max(dot(d, n), 1e-3);
        escapes = rise >= trace_length || !levels_blocked(p + n * EMITTER_OFFSET * voxel + d * rise, p + d * trace_length, p);
    }
#endif
    if (escapes) {
        float width = float(textureSize(world_reflection, 0).x);
        float level = clamp(log2(max(alpha * width / PI, 1.0)), 0.0, float(reflection_levels));
        vec2 uv = vec2(0.5 - atan(r.y, r.x) / (2.0 * PI), 1.0 - acos(clamp(r.z, -1.0, 1.0)) / PI);
        reflection.light += share * textureLod(world_reflection, uv, level).rgb;
    } else {
        reflection.own += vec3(share / PI * intensity);
    }
}

// The reflection at `pixel` (surface point `p`, normal `n`, its G-buffer's glossy texel
// `gloss` and `metallic`: gbuffer_specular), its lookups still to make; all of it times
// the layer's albedo (the DFG term).
Reflection trace_reflection(ivec2 pixel, vec3 p, vec3 n, vec4 gloss, float metallic) {
    Reflection reflection;
    reflection.light = vec3(0.0);
    reflection.own = vec3(0.0);
    reflection.seen = false;
    vec3 v = gbuffer_view(pixel, p);
    float alpha = specular_alpha(gloss.a, 0.0);
    uint h = hash32(uint(pixel.x) * 1973u + hash32(uint(pixel.y) * 9277u
                                                                     + uint(reflection_pattern) * 26699u));
    // the first set traces the mirror direction (a still, noiseless frame); the others draw from the lobe
    vec2 u = reflection_pattern == 0 ? vec2(0.0)
                                     : vec2(hash32(h) & 0xffffu, hash32(h + 1u) & 0xffffu) / 65536.0;
    vec3 r = reflect(-v, n);
    vec3 d = lobe_direction(n, v, alpha, u);
    float screen = 1.0 - smoothstep(SCREEN_ALPHA.x, SCREEN_ALPHA.y, alpha);
    float fade = 0.0;
    if (screen > 0.0) {
        float jitter = float(hash32(h + 2u) & 0xffffu) / 65536.0;
        vec3 start = p + n * (1e-3 * max(distance(p, gbuffer_unproject(pixel, 0.0)), 1e-3));
        ivec2 hit;
        if (screen_trace(start, d, jitter, hit, fade)) add_seen(reflection, hit, screen * fade);
        else fade = 0.0;
    }
    float rest = 1.0 - screen * fade;
    if (rest > 0.0) add_surroundings(reflection, pixel, p, n, r, d, alpha, rest);
    vec3 dfg = specular_albedo(gloss.rgb, metallic, gloss.a, max(dot(n, v), 1e-4));
    reflection.light *= dfg;
    reflection.weight *= dfg;
    reflection.own *= dfg;
    return reflection;
}
