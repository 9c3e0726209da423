#version 450 core
// A point emitter as the camera sees it (its own glow, for the combined image; gpu/
// emitter_grid.py): a sphere of the area it comes from, radiance flux / (pi area), drawn
// as a round point of its projected size, or, smaller than a pixel, one pixel carrying
// its radiance times the share of the pixel it covers.
#include "common.glsl"
#include "emitter.glsl"
layout(std430, binding = 0) readonly buffer Emitters { Emitter emitters[]; };
uniform mat4 view_projection;
uniform vec3 camera_position;
uniform float pixel_angle;   // a pixel's width per unit distance
out vec3 glow_radiance;
out float glow_radius;       // in pixels

void main() {
    Emitter e = emitters[gl_VertexID];
    float area = max(e.normal.w, 1e-30);
    float radius = sqrt(area / (4.0 * PI));
    float dist = max(length(camera_position - e.position.xyz), 1e-30);
    glow_radius = radius / (dist * pixel_angle);
    glow_radiance = e.flux.rgb / (PI * area);
    gl_Position = e.position.w > 0.0 ? view_projection * vec4(e.position.xyz, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
    gl_PointSize = glow_radius < 0.5 ? 1.0 : ceil(2.0 * glow_radius + 1.0);
}
