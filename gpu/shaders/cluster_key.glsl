// A light grid cluster's name (gpu/light_grid.py): its cluster level (the finest of `levels`
// grid levels holding its emitters, or the last grid over the scene), its cell there in cells
// `octave` octaves wider than the level's (cells indexed on the level's `size`-wide lattice),
// its normal's bin (main axis and sign, 6: none) and its emitters' room (rooms.glsl; 0 where
// rooms are not told apart), counted last: outside rooms the names, and so the hash table's
// slots, are what they would be without rooms. A cluster emitter carries it, with its octave,
// in position.w as the bits of a float of at least 2 (position.w > 0: valid): 30 bits hold it
// for grids of up to 128 cells and 5 levels (gpu/settings.py's bounds), 7 octaves and
// ROOM_CODES rooms.
int cluster_key(int level, ivec3 cell, int bin, int room, int size, int levels) {
    return (((level * size + cell.z) * size + cell.y) * size + cell.x) * 7 + bin + room * (levels * size * size * size * 7);
}

void cluster_cell(int key, int size, int levels, out int level, out ivec3 cell, out int bin, out int room) {
    int rooms_apart = levels * size * size * size * 7;
    room = key / rooms_apart;
    key %= rooms_apart;
    bin = key % 7;
    int index = key / 7;
    cell = ivec3(index % size, (index / size) % size, (index / (size * size)) % size);
    level = index / (size * size * size);
}
float cluster_word(int key, int octave) { return intBitsToFloat((key * DEPTH + octave) | 0x40000000); }

int cluster_word_key(float word) { return (floatBitsToInt(word) & 0x3FFFFFFF) / DEPTH; }

int cluster_word_octave(float word) { return (floatBitsToInt(word) & 0x3FFFFFFF) % DEPTH; }
