// The room of the side of its face the camera sees at a pixel (rooms.glsl), from the
// G-buffer's triangles and the faces' bytes, bound at SIDES_BINDING.
#include "face_codes.glsl"
#include "rooms.glsl"
layout(std430, binding = SIDES_BINDING) readonly buffer SidesAndRooms { uint sides_and_rooms[]; };  // a byte a triangle
uniform usampler2D g_triangles;  // gbuffer.frag's: the triangle, bit 31 set where its front side is seen

int seen_room(ivec2 pixel) {
    uint seen = texelFetch(g_triangles, pixel, 0).r;
    return side_room(TRIANGLE_BYTE(sides_and_rooms, seen_triangle(seen)), seen_front(seen));
}
