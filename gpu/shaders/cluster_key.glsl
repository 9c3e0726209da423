// A light grid cluster's name (gpu/light_grid.py): its cluster level (the finest of `levels`
// grid levels holding its emitters, or the last grid over the scene), its cell there in cells
// `octave` octaves wider than the level's (cells indexed on the level's `size`-wide lattice),
// its lobe's bin (a cosine normal's main axis and sign 0-5, 6: none, a glossy lobe's axis
// 7-12: CLUSTER_BINS, gpu/light_grid.py BINS) and its emitters' room (rooms.glsl; 0 where
// rooms are not told apart), counted last: outside rooms the names, and so the hash table's
// slots, are what they would be without rooms. A cluster emitter carries it, with its octave,
// in position.w as the bits of a float of at least 2 (position.w > 0: valid): 30 bits hold it
// for grids of up to 128 cells (clusters of 64) and 5 levels (gpu/settings.py's bounds), 7
// octaves and ROOM_CODES rooms.
const int NO_NORMAL_BIN = 6;
const int GLOSSY_BINS = 7;  // the first glossy lobe's bin

// The bin of a lobe along unit `axis`, glossy or not: its main axis and sign.
int axis_bin(vec3 axis, bool glossy) {
    vec3 a = abs(axis);
    int main_axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    return (glossy ? GLOSSY_BINS : 0) + 2 * main_axis + (axis[main_axis] < 0.0 ? 1 : 0);
}
int cluster_key(int level, ivec3 cell, int bin, int room, int size, int levels) {
    return (((level * size + cell.z) * size + cell.y) * size + cell.x) * CLUSTER_BINS + bin + room * (levels * size * size * size * CLUSTER_BINS);
}

void cluster_cell(int key, int size, int levels, out int level, out ivec3 cell, out int bin, out int room) {
    int rooms_apart = levels * size * size * size * CLUSTER_BINS;
    room = key / rooms_apart;
    key %= rooms_apart;
    bin = key % CLUSTER_BINS;
    int index = key / CLUSTER_BINS;
    cell = ivec3(index % size, (index / size) % size, (index / (size * size)) % size);
    level = index / (size * size * size);
}
float cluster_word(int key, int octave) { return intBitsToFloat((key * DEPTH + octave) | 0x40000000); }

int cluster_word_key(float word) { return (floatBitsToInt(word) & 0x3FFFFFFF) / DEPTH; }

int cluster_word_octave(float word) { return (floatBitsToInt(word) & 0x3FFFFFFF) % DEPTH; }
