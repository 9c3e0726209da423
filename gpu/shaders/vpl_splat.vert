#version 450 core
// One VPL as a point of the camera image (the VPL Splats pass), pulled toward the camera
// far enough that the surface it stands on, seen at any angle, does not hide its splat:
// the splat's radius in world units times the tangent of the viewing angle, plus a pixel.
layout(std430, binding = 0) readonly buffer VPLs { vec4 vpl_data[]; };  // position (w valid), normal, flux
uniform mat4 view_projection;
uniform vec3 camera_position;
uniform float pixel_angle;   // a pixel's width per unit distance
uniform float point_size;
out vec3 splat_flux;

void main() {
    vec4 p = vpl_data[3 * gl_VertexID];
    vec3 n = vpl_data[3 * gl_VertexID + 1].xyz;
    splat_flux = vpl_data[3 * gl_VertexID + 2].rgb;
    vec3 to_camera = camera_position - p.xyz;
    float dist = length(to_camera);
    float c = clamp(abs(dot(to_camera / max(dist, 1e-30), n)), 0.05, 1.0);
    float pull = dist * pixel_angle * (1.0 + 0.5 * point_size * sqrt(1.0 - c * c) / c);
    vec3 q = p.xyz + to_camera * min(pull / max(dist, 1e-30), 0.5);
    gl_Position = p.w > 0.0 ? view_projection * vec4(q, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);  // invalid: clipped
    gl_PointSize = point_size;
}
