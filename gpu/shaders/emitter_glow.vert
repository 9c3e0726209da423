#version 450 core
// A point emitter as the camera sees it (its own glow, for the combined image; gpu/
// emitter_grid.py): a sphere whose surface is the area it comes from, of radiance flux /
// (pi area), drawn as a round point of its projected size; smaller than a pixel, one
// pixel carrying its radiance times the share of the pixel it covers, which is its
// intensity flux / (4 pi) over the squared distance and the pixel's solid angle (no
// division by a vanishing area).
#include "common.glsl"
#include "emitter.glsl"
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
uniform mat4 view_projection;
uniform vec3 camera_position;
uniform float pixel_angle;   // a pixel's width per unit distance
out vec3 glow_radiance;      // of the disc, or of the one pixel
out float glow_radius;       // in pixels

void main() {
    Emitter e = emitters[gl_VertexID];
    float dist = max(length(camera_position - e.position.xyz), 1e-30);
    glow_radius = sqrt(e.normal.w / (4.0 * PI)) / (dist * pixel_angle);
    glow_radiance = glow_radius < 0.5 ? e.flux.rgb / (4.0 * PI) / (dist * dist * pixel_angle * pixel_angle)
                                      : e.flux.rgb / (PI * e.normal.w);
    gl_Position = e.position.w > 0.0 ? view_projection * vec4(e.position.xyz, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
    gl_PointSize = glow_radius < 0.5 ? 1.0 : ceil(2.0 * glow_radius + 1.0);
}
