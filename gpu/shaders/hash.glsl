// Chris Wellons' lowbias32 integer hash: the shaders' random numbers (hashed cut-outs, soft
// shadows' rotations, reflections' rays, the bounces' points), each seeded by what it
// varies with.
uint hash32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// A number in [0, 1) from a hash: its top 24 bits.
float hash_unit(uint h) {
    return float(h >> 8) / 16777216.0;
}
