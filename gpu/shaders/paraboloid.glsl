// Paraboloid projection (thesis eq. 3) of a point in hemisphere space (+z the axis).
// Returns (s, t) in the unit disk; points straight behind are guarded, not divided by 0.
vec2 paraboloid_project(vec3 p) {
    float len = length(p);
    return p.xy / max(len + p.z, 1e-7 * len + 1e-30);
}

// Direction of map point (s, t): d = (2s, 2t, 1 - s^2 - t^2) / (1 + s^2 + t^2).
vec3 paraboloid_direction(vec2 st) {
    float r2 = dot(st, st);
    return vec3(2.0 * st, 1.0 - r2) / (1.0 + r2);
}

// Solid angle of a texel of size (2/R)^2 in map units at (s, t): 4 dA / (1 + s^2 + t^2)^2.
float paraboloid_texel_solid_angle(vec2 st, float resolution) {
    float r2 = dot(st, st);
    return 4.0 * 4.0 / (resolution * resolution) / ((1.0 + r2) * (1.0 + r2));
}

// Clip-space position of hemisphere-space point p (z >= 0) in a paraboloid map: eq. 3
// then the light distance in [near, far] as depth. w = 1, so the rasterizer interpolates
// linearly between projected vertices.
vec4 paraboloid_clip_position(vec3 p, float near, float far) {
    float depth = clamp((length(p) - near) / (far - near), 0.0, 1.0);
    return vec4(paraboloid_project(p), depth * 2.0 - 1.0, 1.0);
}
