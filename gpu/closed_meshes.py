"""Which side of each face light can reach, and which room it looks into. A closed mesh
(Scene.solids) with nothing that emits inside it bounds a solid: no light reaches the side
of its faces that looks in, however thin it is. The occupancy cannot tell: a floor slab or
a wall thinner than two voxels fills its voxels from face to face, and a point on its
underside, gathering for the side that looks into the slab, would see the sky through it.
A closed mesh that holds a lamp is a room: that lamp lights only what lies in it, and
what lies outside it only the lights outside; a side in a room no light lies in gets
none (docs/method.md, "Closed meshes").
"""
import numpy as np

FRONT, BACK = 1, 2  # the side a triangle's winding normal faces, and the other
OPEN = FRONT | BACK
FRONT_ROOM_SHIFT, BACK_ROOM_SHIFT = 2, 5
"""Where a face's byte holds the room each side looks into (three bits each, 0: outside
every room), above its open sides (bits 0 and 1)."""
MAX_ROOMS = 7
ROOM_CODES = MAX_ROOMS + 1
"""Rooms 0 (outside every room) to MAX_ROOMS: what three bits hold (shaders/rooms.glsl)."""
ROOM_CODE_DEFINES = {"ROOM_CODES": ROOM_CODES, "FRONT_ROOM_SHIFT": FRONT_ROOM_SHIFT, "BACK_ROOM_SHIFT": BACK_ROOM_SHIFT}
"""The defines shaders/rooms.glsl reads."""
ROOM_DEFINES = {**ROOM_CODE_DEFINES, "ROOMS": 1}
"""A shader's defines where it keeps light in its room."""
ROOM_TESTS = 4_000_000
"""Face centres tested against a room's triangles, summed over the rooms (each centre
within a room's box against each of its triangles): beyond it, faces are not sorted into
rooms, and lamps light every room as before."""
INSIDE_TESTS = 256
"""Point emitters and emissive triangles, each strided to at most this many, tested for
lying inside a closed mesh (lamps are all tested): one is enough to make it a room."""
RAY = np.array([0.5773, 0.5781, 0.5766]) / np.linalg.norm([0.5773, 0.5781, 0.5766])
"""The direction of the parity test's ray: off every axis and diagonal, so it meets no
edge of an axis-aligned mesh."""


def side_rooms(sides):
    """The room the front and the back side of each face looks into, from the sides
    array of `ClosedMeshes.sides_and_rooms` ((T,) uint8 each)."""
    return (sides >> FRONT_ROOM_SHIFT) & (ROOM_CODES - 1), (sides >> BACK_ROOM_SHIFT) & (ROOM_CODES - 1)


class ClosedMeshes:
    """A sanitized scene's closed meshes (Scene.solids): which of them could be solids or
    rooms, by their shape and surfaces alone (a volume, nothing that lets light through,
    shadows cast: kept per geometry), and `sides_and_rooms` per frame's emitters."""

    def __init__(self, scene):
        pieces = np.asarray(scene.solids) if scene.solids is not None else np.zeros(0, np.int32)
        faces = np.flatnonzero(pieces >= 0)
        self.pieces = pieces
        self.order = faces[np.argsort(pieces[faces], kind="stable")]
        self.names, self.starts = np.unique(pieces[self.order], return_index=True)
        self.ends = np.append(self.starts[1:], len(self.order))
        self._face_rooms = {}  # rooms (their indices, innermost first) -> (front, back) or None
        self._last_sides = None  # (the solids and rooms it was made for, the last sides array)
        if not len(self.order):
            self.candidate = np.zeros(0, dtype=bool)
            return
        self.triangles = scene.triangles
        corners = np.asarray(self.triangles[self.order], dtype=np.float64)
        self.volume = np.add.reduceat(np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])),
                                      self.starts) / 6.0
        self.low = np.minimum.reduceat(corners.min(axis=1), self.starts)
        self.high = np.maximum.reduceat(corners.max(axis=1), self.starts)
        self.candidate = np.abs(self.volume) > 1e-6 * np.max(self.high - self.low, axis=1) ** 3
        see_through = _see_through(scene)
        if see_through is not None:
            self.candidate &= ~np.logical_or.reduceat(see_through[self.order], self.starts)
        first, count = scene.light_triangles or (0, scene.triangle_count)  # those that cast shadows
        self.candidate &= np.logical_and.reduceat((self.order >= first) & (self.order < first + count), self.starts)

    def sides_and_rooms(self, scene):
        """(T,) uint8 per triangle, the sides (FRONT, BACK) light can reach and the room each
        looks into (FRONT_ROOM_SHIFT, BACK_ROOM_SHIFT), and the Rooms; None for the first
        where every side of every triangle is open and outside every room, for the second
        where there are no rooms. A candidate that holds a lamp (not a sun), a point emitter
        or another mesh's emissive triangle is open on both sides. The same array again
        while the same candidates are solids and the same rooms lit."""
        if not self.candidate.any():
            return None, None
        lamps = [np.asarray(light.position, dtype=np.float64) for light in scene.lights if light.kind != "SUN"]
        held = [self._holding(lamp, self.candidate) for lamp in lamps]  # the closed meshes each lamp lies in
        solid = self.candidate.copy()
        solid[sorted(set().union(*held))] = False
        points, owners = _emitter_points(scene, self.pieces)
        for point, owner in zip(points, owners):
            solid[list(self._holding(point, solid & (self.names != owner)))] = False
        rooms = self._rooms(scene, lamps, held)
        if not solid.any() and rooms is None:
            return None, None
        made = (np.flatnonzero(solid).tobytes(), None if rooms is None else rooms.key)
        if self._last_sides is not None and self._last_sides[0] == made:  # lamps moved within their rooms
            return self._last_sides[1], rooms
        code = np.full(int(self.pieces.max()) + 1, OPEN, dtype=np.uint8)
        code[self.names[solid]] = np.where(self.volume[solid] > 0, FRONT, BACK)
        sides = np.where(self.pieces >= 0, code[np.maximum(self.pieces, 0)], OPEN).astype(np.uint8)
        if rooms is not None:
            front, back = rooms.faces
            if rooms.lit is not None:
                sides &= ~np.where(np.isin(front, rooms.lit), 0, FRONT).astype(np.uint8)
                sides &= ~np.where(np.isin(back, rooms.lit), 0, BACK).astype(np.uint8)
            sides |= (front << FRONT_ROOM_SHIFT).astype(np.uint8) | (back << BACK_ROOM_SHIFT).astype(np.uint8)
        self._last_sides = (made, sides)
        return sides, rooms

    def _rooms(self, scene, lamps, held):
        """The scene's Rooms: the closed meshes some of its `lamps` (not suns) lie in (`held`,
        the indices of those each lies in); None where none does, more than MAX_ROOMS do or
        sorting the faces would take over ROOM_TESTS."""
        holding = sorted(set().union(*held), key=lambda index: abs(self.volume[index]))  # innermost first
        if not holding or len(holding) > MAX_ROOMS:
            return None
        lamp_rooms = {tuple(np.round(lamp, 9)): next((number for number, index in enumerate(holding, start=1)
                                                      if index in inside), 0) for lamp, inside in zip(lamps, held)}
        if tuple(holding) not in self._face_rooms:
            self._face_rooms[tuple(holding)] = self._sort_faces(holding)
        faces = self._face_rooms[tuple(holding)]
        if faces is None:
            return None
        lit = None if scene.point_emitter_count or scene.emission is not None else \
            np.array(sorted(set(lamp_rooms.values()) | ({0} if _lit_outside(scene) else set())), dtype=np.uint8)
        return Rooms(self, holding, *faces, lit, lamp_rooms)

    def _sort_faces(self, holding):
        """The room each side of each face looks into, (front, back), for the rooms
        `holding` (innermost first); None over ROOM_TESTS. Kept per rooms: a lamp moved
        within its room sorts nothing again."""
        centres = np.asarray(self.triangles, dtype=np.float64).mean(axis=1)
        within = [np.flatnonzero(np.all((centres >= self.low[index]) & (centres <= self.high[index]), axis=1) &
                                 (self.pieces != self.names[index])) for index in holding]
        if sum(len(faces) * (self.ends[index] - self.starts[index]) for faces, index in zip(within, holding)) > ROOM_TESTS:
            return None
        room = np.zeros(len(centres), dtype=np.uint8)
        for number, index, faces in reversed(list(zip(range(1, len(holding) + 1), holding, within))):
            room[faces[_inside_all(centres[faces], self.corners(index))]] = number
        front, back = room.copy(), room.copy()
        for number, index in enumerate(holding, start=1):
            own = self.order[self.starts[index]:self.ends[index]]
            (back if self.volume[index] > 0 else front)[own] = number  # the side that looks in
        return front, back

    def _holding(self, point, among):
        """The indices of the closed meshes `among` (bool per closed mesh) `point` lies in."""
        boxed = among & np.all((point >= self.low) & (point <= self.high), axis=1)
        return {int(index) for index in np.flatnonzero(boxed) if _inside(point, self.corners(index))}

    def faces(self, index):
        """The numbers of closed mesh `index`'s triangles in the scene."""
        return self.order[self.starts[index]:self.ends[index]]

    def corners(self, index):
        """The triangles (m, 3, 3) float64 of closed mesh `index`."""
        return np.asarray(self.triangles[self.faces(index)], dtype=np.float64)

    def emitters_key(self, scene):
        """What `sides_and_rooms` depends on beyond the geometry: where the lamps (not suns) and
        the point emitters are, and whether a sun or the world lights the outside."""
        lamps = tuple(tuple(np.round(light.position, 9)) for light in scene.lights if light.kind != "SUN")
        return lamps, scene.point_emitters_key(), _lit_outside(scene)


class Rooms:
    """The rooms of a scene (closed meshes a lamp lies in, numbered from 1 innermost first;
    0 is outside every room): `faces`, the room each side of each face looks into (front
    and back, (T,) uint8 each); `lit`, the rooms some light lies in (None: any may be, as
    where point emitters or emissive surfaces are, which are not all tested)."""

    def __init__(self, closed, holding, front, back, lit, lamp_rooms):
        self.closed, self.holding = closed, holding
        self.faces = (front, back)
        self.lit = lit
        self.key = (tuple(holding), None if lit is None else lit.tobytes())
        """What the rooms' numbers, shapes and lit ones depend on, beside the geometry."""
        self._lamp_rooms = lamp_rooms  # a lamp's position, rounded -> its room

    @property
    def count(self):
        """The rooms, numbered 1 to count (0 is outside every room)."""
        return len(self.holding)

    def walls(self):
        """The rooms' triangles (their numbers in the scene, int32), room 1's first, and
        each room's first of them, their count and its box (low and high corners)."""
        closed = self.closed
        faces = [closed.faces(index) for index in self.holding]
        counts = np.array([len(f) for f in faces], dtype=np.int32)
        firsts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int32)
        return (np.concatenate(faces).astype(np.int32), firsts, counts,
                closed.low[self.holding], closed.high[self.holding])

    def room_of(self, light):
        """The room `light` lies in (0: none; a sun's is outside every room)."""
        if light.kind == "SUN":
            return 0
        key = tuple(np.round(np.asarray(light.position, dtype=np.float64), 9))
        if key not in self._lamp_rooms:
            inside = self.closed._holding(np.asarray(key), self.closed.candidate)
            self._lamp_rooms[key] = next((number for number, index in enumerate(self.holding, start=1)
                                          if index in inside), 0)
        return self._lamp_rooms[key]


def _lit_outside(scene):
    return any(light.kind == "SUN" for light in scene.lights) or \
        (scene.world is not None and scene.world.lights_anything)


def _see_through(scene):
    """(T,) bool: the triangles that let some light through; None where none does."""
    through = np.zeros(scene.triangle_count, dtype=bool)
    if scene.alpha is not None:
        through |= scene.alpha < 1.0
    if scene.alpha_layers is not None:
        through |= scene.alpha_layers >= 0
    if scene.transmission is not None:
        through |= scene.transmission[:, 3] > 0.0
    return through if through.any() else None


def _emitter_points(scene, pieces):
    """Points where light starts within the scene other than lamps, and the closed mesh
    each lies on (-1: none): point emitters and emissive triangles' centres."""
    points, owners = [np.zeros((0, 3))], [np.zeros(0, dtype=int)]
    if scene.point_emitters is not None and len(scene.point_emitters):
        rows = scene.point_emitters  # every so many, taken before the float64 copy: a million rows move each frame
        points.append(np.asarray(rows[::max(1, -(-len(rows) // INSIDE_TESTS)), :3], dtype=np.float64))
        owners.append(np.full(len(points[-1]), -1))
    if scene.emission is not None:
        emissive = np.flatnonzero(np.asarray(scene.emission).max(axis=1) > 0.0)
        emissive = emissive[::max(1, -(-len(emissive) // INSIDE_TESTS))]
        points.append(np.asarray(scene.triangles, dtype=np.float64)[emissive].mean(axis=1))
        owners.append(pieces[emissive])
    return np.concatenate(points), np.concatenate(owners)


def _inside_all(points, corners):
    """(n,) bool: which of `points` (n, 3) lie inside the closed surface `corners` (m, 3, 3),
    in batches of about a million point-triangle pairs."""
    batch = max(1, (1 << 20) // max(len(corners), 1))
    return np.concatenate([_crossings(points[i:i + batch], corners) % 2 == 1 for i in range(0, len(points), batch)]
                          or [np.zeros(0, dtype=bool)])


def _crossings(points, corners):
    """(n,) how many times a ray from each of `points` (n, 3) crosses the triangles
    `corners` (m, 3, 3): inside a closed surface, an odd number (Möller and Trumbore 1997)."""
    edge1, edge2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    p = np.cross(RAY, edge2)
    det = np.einsum("ij,ij->i", edge1, p)
    usable = np.abs(det) > 1e-30
    inverse = np.where(usable, 1.0 / np.where(usable, det, 1.0), 0.0)
    s = points[:, None, :] - corners[None, :, 0]
    u = np.einsum("nij,ij->ni", s, p) * inverse
    q = np.cross(s, edge1[None])
    v = (q @ RAY) * inverse
    t = np.einsum("ij,nij->ni", edge2, q) * inverse
    return np.count_nonzero(usable & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > 0.0), axis=1)


def _inside(point, corners):
    """Whether `point` lies inside the closed surface of triangles `corners` (m, 3, 3)."""
    return bool(_crossings(np.asarray(point, dtype=np.float64)[None], corners)[0] % 2)
