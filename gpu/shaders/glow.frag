#version 450 core
// The radiance of the emissive surfaces the camera sees (their own glow, for the combined
// image): each triangle's emission, read by its number (raster.vert), where the G-buffer's
// depth says the triangle is the one seen; no share of the pixel covered in front of it
// (alpha 0: the surface seen is the one that glows).
layout(std430, binding = 0) readonly buffer Emission { vec4 emission[]; };
flat in int surface_triangle;
layout(location = 0) out vec4 out_glow;

void main() {
    out_glow = vec4(emission[surface_triangle].rgb, 0.0);
}
