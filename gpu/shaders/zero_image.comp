#version 450 core
// Zeroes a float image on the GPU (gpu/context.py GLContext.clear): a framebuffer's
// colour clear of RGBA32F images is several times slower on the H100
// (docs/performance.md, "Clears").
layout(local_size_x = 8, local_size_y = 8) in;
layout(FORMAT, binding = 0) writeonly uniform image2D image;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (all(lessThan(texel, imageSize(image)))) imageStore(image, texel, vec4(0.0));
}
