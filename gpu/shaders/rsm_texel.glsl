// Copying an RSM texel into a texel of another solid angle: the flux it reflects and the
// surfel area it stands for scale with the ratio of solid angles (target over source).
void copy_rsm_texel(sampler2D position_map, sampler2D normal_map, sampler2D flux_map, ivec2 texel, float ratio,
                    out vec4 position, out vec4 normal, out vec4 flux) {
    position = texelFetch(position_map, texel, 0);
    normal = texelFetch(normal_map, texel, 0);
    flux = texelFetch(flux_map, texel, 0);
    normal.w *= ratio;
    flux.rgb *= ratio;
}
