#version 450 core
// Multiplies the G-buffer's albedo by the tint of the transmitting surfaces in front of it
// (passing_tint.frag's image): what is seen through glass is tinted, in every pass that
// reads the G-buffer.
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32ui, binding = 0) uniform uimage2D g_surface_image;
uniform sampler2D passing_tint;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, imageSize(g_surface_image)))) return;
    vec3 tint = texelFetch(passing_tint, pixel, 0).rgb;
    if (all(greaterThanEqual(tint, vec3(1.0)))) return;
    uvec4 surface = imageLoad(g_surface_image, pixel);
    surface.yzw = floatBitsToUint(uintBitsToFloat(surface.yzw) * tint);
    imageStore(g_surface_image, pixel, surface);
}
