// An RSM texel's flux.w (rsm_surface.glsl): the share of its flux that its glossy layer
// reflects (of the channels' sum, below 1) plus its roughness in 255ths, an integer, so
// that the glossy VPLs (vpl_gather.comp) find both where the maps were copied or warped.
float glossy_word(float share, float roughness) {
    return round(clamp(roughness, 0.0, 1.0) * 255.0) + clamp(share, 0.0, 0.999);
}

float glossy_word_share(float word) { return word - floor(word); }

float glossy_word_roughness(float word) { return floor(word) / 255.0; }
