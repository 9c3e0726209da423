#version 450 core
// Zeroes a buffer on the GPU (gpu/context.py zero_buffer): moderngl's clear writes it
// through a mapping from the CPU, milliseconds for a few MB on a discrete GPU.
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Words { uint words[]; };
uniform int word_count;
uniform int first_word;

void main() {
    int index = first_word + int(gl_GlobalInvocationID.x);
    if (index < word_count) words[index] = 0u;
}
