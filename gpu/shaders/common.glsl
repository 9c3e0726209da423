// Shared constants and the 2-band SH basis in the order [Y00, Y1-1, Y10, Y11] (METHOD §7).
const float PI = 3.14159265358979;
const float SH_C0 = 0.282094792;    // 1 / (2 sqrt(pi))
const float SH_C1 = 0.488602512;    // sqrt(3 / (4 pi))
const float LOBE_C0 = 0.886226925;  // sqrt(pi) / 2
const float LOBE_C1 = 1.023326708;  // sqrt(pi / 3)

vec4 sh_basis(vec3 w) {
    return vec4(SH_C0, -SH_C1 * w.y, SH_C1 * w.z, -SH_C1 * w.x);
}

// Solid angle of a cube-face texel at face coordinates uv in [-1, 1]^2 (METHOD §2).
float cube_texel_solid_angle(vec2 uv, float resolution) {
    return 4.0 / (resolution * resolution) / pow(1.0 + dot(uv, uv), 1.5);
}

// SH projection of the clamped cosine max(0, n.w): peak 1, integral pi.
vec4 cos_lobe(vec3 n) {
    return vec4(LOBE_C0, -LOBE_C1 * n.y, LOBE_C1 * n.z, -LOBE_C1 * n.x);
}
