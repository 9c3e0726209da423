#version 450 core
// A point emitter's disc (emitter_glow.vert), covering the pixel (alpha 1); overlapping ones add up.
in vec3 glow_radiance_out;
in float glow_radius_out;
layout(location = 0) out vec4 out_glow;

void main() {
    if (length(gl_PointCoord - 0.5) * ceil(2.0 * glow_radius_out + 1.0) > glow_radius_out) discard;
    out_glow = vec4(glow_radiance_out, 1.0);
}
