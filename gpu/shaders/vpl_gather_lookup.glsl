// Irradiance gathered at the pixel (vpl_gather_pixels.comp, filtered).
uniform sampler2D gathered;
