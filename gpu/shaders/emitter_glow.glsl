// A point emitter as the camera sees it (its own glow, for the combined image; gpu/
// emitter_grid.py): a sphere whose surface is the area it comes from, of radiance flux /
// (pi area), a round disc of its projected size; smaller than a pixel, one pixel carrying
// its radiance times the share of the pixel it covers, which is its intensity flux /
// (4 pi) over the squared distance and the pixel's solid angle (no division by a
// vanishing area). Read by point_glow.comp.
uniform vec3 camera_position;
uniform float pixel_angle;   // a pixel's width per unit distance

// The disc's radius in pixels.
float glow_radius(Emitter e) {
    float dist = max(length(camera_position - e.position.xyz), 1e-30);
    return sqrt(e.normal.w / (4.0 * PI)) / (dist * pixel_angle);
}

// The radiance of the disc, or of its one pixel when `radius` (glow_radius) is below half a pixel.
vec3 glow_radiance(Emitter e, float radius) {
    if (radius >= 0.5) return e.flux.rgb / (PI * e.normal.w);
    vec3 d = camera_position - e.position.xyz;
    return e.flux.rgb / (4.0 * PI) / max(dot(d, d) * pixel_angle * pixel_angle, 1e-30);
}
