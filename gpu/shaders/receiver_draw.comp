#version 450 core
// Points drawn on the surfaces the lights see (gpu/emitter_bounce.py Receivers): `count`
// points stratified over the light triangles' cumulative area, each uniform within its
// triangle, with the random numbers of `seed`; each a Receiver of emitter_bounce.comp:
// position, face normal and the area each stands for, the colour its triangle bounces and
// its triangle's byte: the sides of it light reaches and the rooms they look into
// (gpu/closed_meshes.py).
#include "hash.glsl"
#include "face_codes.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };    // nine a triangle (mesh_buffer.py)
layout(std430, binding = 1) readonly buffer Cumulative { float cumulative[]; };  // area shares summed, last 1
layout(std430, binding = 2) readonly buffer Colours { vec4 colours[]; };        // a light triangle's bounce colour
layout(std430, binding = 3) readonly buffer OpenSides { uint open_sides[]; };   // a byte a scene triangle
struct Receiver { vec4 position; vec4 normal; vec3 albedo; float code; };
layout(std430, binding = 4) writeonly buffer Receivers { Receiver receivers[]; };
uniform int count;
uniform int triangles;     // the light triangles
uniform int first;         // the first light triangle's number in the scene
uniform uint seed;
uniform float area_each;   // the light triangles' area over `count`
uniform bool sides_known;  // else light reaches every side (OPEN), outside every room

vec3 corner(int triangle, int k) {
    int at = 9 * triangle + 3 * k;
    return vec3(positions[at], positions[at + 1], positions[at + 2]);
}

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= count) return;
    uint h = hash32(uint(i) ^ hash32(seed + 0x9e3779b9u));
    float u = (float(i) + hash_unit(h)) / float(count);
    int low = 0, high = triangles - 1;  // the first triangle whose cumulative share reaches u
    while (low < high) {
        int middle = (low + high) / 2;
        if (cumulative[middle] < u) low = middle + 1; else high = middle;
    }
    int t = first + low;
    vec3 a = corner(t, 0), b = corner(t, 1), c = corner(t, 2);
    float root = sqrt(hash_unit(hash32(h + 1u))), v = hash_unit(hash32(h + 2u));
    vec3 p = (1.0 - root) * a + root * (1.0 - v) * b + root * v * c;
    vec3 across = cross(b - a, c - a);
    vec3 n = dot(across, across) > 0.0 ? normalize(across) : vec3(0.0, 0.0, 1.0);
    uint code = sides_known ? TRIANGLE_BYTE(open_sides, t) : uint(OPEN);
    receivers[i] = Receiver(vec4(p, 1.0), vec4(n, area_each), colours[low].rgb, float(code));
}
