// What a pass reads of a triangle by its number: which triangle a G-buffer pixel sees and
// from which side (gbuffer.frag sets bit 31 where it sees the front, the side its winding
// faces), and a triangle's byte in a buffer of one byte a triangle read as uints
// (gpu/closed_meshes.py: the sides light reaches and the rooms they look into).
int seen_triangle(uint seen) {
    return int(seen & 0x7fffffffu);
}

bool seen_front(uint seen) {
    return (seen >> 31) == 1u;
}

#define TRIANGLE_BYTE(bytes, triangle) ((bytes[(triangle) >> 2] >> (8 * ((triangle) & 3))) & 255u)
