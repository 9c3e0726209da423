// Rooms (gpu/closed_meshes.py): a face's byte holds the room each of its sides looks into
// (three bits each, at FRONT_ROOM_SHIFT and BACK_ROOM_SHIFT; 0 is outside every room), and
// an emitter's position.w is 1 + the room it lies in: a VPL its light's, a point a bounce
// lit its side's. Light stays in its room: nothing gathers an emitter of another.

// The room the front (the side the winding faces) or back side of a face looks into.
int side_room(uint code, bool front) {
    return int(code >> (front ? FRONT_ROOM_SHIFT : BACK_ROOM_SHIFT)) & (ROOM_CODES - 1);
}

// The room of an emitter of position `position` (a VPL's or a bounced point's, not a cluster's).
int emitter_room(vec4 position) { return clamp(int(position.w) - 1, 0, ROOM_CODES - 1); }

// The position.w of an emitter in `room`.
float room_word(int room) { return float(1 + room); }
