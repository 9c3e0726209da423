// Irradiance from an LPV grid (cosine convolution, METHOD §7): the SH of radiant intensity
// per cell at p + n cell/2, against the clamped cosine around -n, over the cell's face area;
// every grid answers (a fourth component of 1: light_grid_levels.glsl); `toward` (the
// light grid's) is not needed.
uniform sampler3D lpv_r[GRIDS];
uniform sampler3D lpv_g[GRIDS];
uniform sampler3D lpv_b[GRIDS];

vec4 grid_irradiance(int grid, vec3 p, vec3 n, vec3 toward) {
    float cell = cell_sizes[grid];
    vec3 uvw = (p + 0.5 * cell * n - grid_origins[grid]) / (cell * float(grid_size));
    vec4 lobe = cos_lobe(-n);
    vec3 intensity = vec3(dot(texture(lpv_r[grid], uvw), lobe), dot(texture(lpv_g[grid], uvw), lobe),
                          dot(texture(lpv_b[grid], uvw), lobe));
    return vec4(max(intensity, 0.0) / (cell * cell), 1.0);
}
