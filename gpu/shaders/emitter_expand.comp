#version 450 core
// Point emitters as the scene holds them (gpu/scene.py point_emitters: position xyz,
// flux rgb, area; seven floats each) into shaders/emitter.glsl rows of isotropic
// emitters (gpu/emitter_grid.py): the CPU neither converts nor uploads the wider rows.
#include "common.glsl"
#include "emitter.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Packed { float columns[]; };
layout(std430, binding = 1) writeonly buffer Emitters { Emitter emitters[]; };
uniform int emitter_count;
uniform int first_emitter;  // this dispatch's first (a dispatch reaches 65,535 workgroups)

void main() {
    int index = first_emitter + int(gl_GlobalInvocationID.x);
    if (index >= emitter_count) return;
    int at = POINT_EMITTER_COLUMNS * index;
    Emitter e;
    e.position = vec4(columns[at], columns[at + 1], columns[at + 2], 1.0);
    e.normal = vec4(0.0, 0.0, 0.0, columns[at + 6]);
    e.flux = vec4(columns[at + 3], columns[at + 4], columns[at + 5], 0.0);
    emitters[index] = e;
}
