// Rooms (gpu/closed_meshes.py): a face's byte holds the room each of its sides looks into
// (three bits each, at FRONT_ROOM_SHIFT and BACK_ROOM_SHIFT; 0 is outside every room), and
// an emitter's position.w is 1 + the room it lies in: a VPL its light's, a point a bounce
// lit or an emissive surface's sample its side's, the world's 0; a point emitter's
// (particles, lamps drawn as emitters) is 1 + ROOM_CODES, any room, as its room is not
// told. Light stays in its room: nothing gathers an emitter of another.

const int ANY_ROOM = -1;

// The room the front (the side the winding faces) or back side of a face looks into.
int side_room(uint code, bool front) {
    return int(code >> (front ? FRONT_ROOM_SHIFT : BACK_ROOM_SHIFT)) & (ROOM_CODES - 1);
}

// The room of an emitter of position `position` (not a light grid cluster's), or ANY_ROOM.
int emitter_room(vec4 position) {
    int code = int(position.w) - 1;
    return code >= ROOM_CODES ? ANY_ROOM : max(code, 0);
}

// Whether an emitter of position `position` lights what lies in `room`.
bool lights_room(vec4 position, int room) {
    int own = emitter_room(position);
    return own == room || own == ANY_ROOM;
}

// The position.w of an emitter in `room` (ANY_ROOM: in any).
float room_word(int room) { return float(1 + (room == ANY_ROOM ? ROOM_CODES : room)); }
