#version 450 core
// A round splat carrying the VPL's flux (W); overlapping splats add up. Pixels whose
// centre lies within the splat's radius plus half a pixel are kept, so a one-pixel splat
// always lands on the pixel under it.
in vec3 splat_flux;
uniform float point_size;
layout(location = 0) out vec4 out_flux;

void main() {
    if (length(gl_PointCoord - 0.5) * point_size > 0.5 * point_size + 0.5) discard;
    out_flux = vec4(splat_flux, 1.0);
}
