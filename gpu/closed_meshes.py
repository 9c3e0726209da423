"""Which side of each face light can reach. A closed mesh (Scene.solids) with nothing
that emits inside it bounds a solid: no light reaches the side of its faces that looks
in, however thin it is. The occupancy cannot tell: a floor slab or a wall thinner than
two voxels fills its voxels from face to face, and a point on its underside, gathering
for the side that looks into the slab, would see the sky through it
(docs/method.md, "Closed meshes").
"""
import numpy as np

FRONT, BACK = 1, 2  # the side a triangle's winding normal faces, and the other
OPEN = FRONT | BACK
INSIDE_TESTS = 256
"""Point emitters and emissive triangles, each strided to at most this many, tested for
lying inside a closed mesh (lamps are all tested): one is enough to make it a room."""
RAY = np.array([0.5773, 0.5781, 0.5766]) / np.linalg.norm([0.5773, 0.5781, 0.5766])
"""The direction of the parity test's ray: off every axis and diagonal, so it meets no
edge of an axis-aligned mesh."""


class ClosedMeshes:
    """A sanitized scene's closed meshes (Scene.solids): which of them could be solids, by
    their shape and surfaces alone (kept per geometry), and `open_sides` per frame's
    emitters."""

    def __init__(self, scene):
        pieces = np.asarray(scene.solids) if scene.solids is not None else np.zeros(0, np.int32)
        faces = np.flatnonzero(pieces >= 0)
        self.pieces = pieces
        self.order = faces[np.argsort(pieces[faces], kind="stable")]
        self.names, self.starts = np.unique(pieces[self.order], return_index=True)
        self.ends = np.append(self.starts[1:], len(self.order))
        if not len(self.order):
            self.candidate = np.zeros(0, dtype=bool)
            return
        corners = np.asarray(scene.triangles, dtype=np.float64)[self.order]
        self.volume = np.add.reduceat(np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])),
                                      self.starts) / 6.0
        self.low = np.minimum.reduceat(corners.min(axis=1), self.starts)
        self.high = np.maximum.reduceat(corners.max(axis=1), self.starts)
        self.candidate = np.abs(self.volume) > 1e-6 * np.max(self.high - self.low, axis=1) ** 3
        see_through = _see_through(scene)
        if see_through is not None:
            self.candidate &= ~np.logical_or.reduceat(see_through[self.order], self.starts)

    def open_sides(self, scene):
        """(T,) uint8 per triangle: the sides (FRONT, BACK) light can reach; None where
        every side of every triangle is open. A candidate that holds a lamp (not a sun), a
        point emitter or another mesh's emissive triangle is a room: both sides open."""
        if not self.candidate.any():
            return None
        solid = self.candidate.copy()
        points, owners = _emitter_points(scene, self.pieces)
        for point, owner in zip(points, owners):
            inside_box = solid & np.all((point >= self.low) & (point <= self.high), axis=1) & (self.names != owner)
            for index in np.flatnonzero(inside_box):
                corners = scene.triangles[self.order[self.starts[index]:self.ends[index]]].astype(np.float64)
                if _inside(point, corners):
                    solid[index] = False
        if not solid.any():
            return None
        code = np.full(int(self.pieces.max()) + 1, OPEN, dtype=np.uint8)
        code[self.names[solid]] = np.where(self.volume[solid] > 0, FRONT, BACK)
        return np.where(self.pieces >= 0, code[np.maximum(self.pieces, 0)], OPEN).astype(np.uint8)

    def emitters_key(self, scene):
        """What `open_sides` depends on beyond the geometry: where the lamps (not suns) and
        the point emitters are."""
        lamps = tuple(tuple(np.round(light.position, 9)) for light in scene.lights if light.kind != "SUN")
        return lamps, scene.point_emitters_key()


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
    """Points where light starts within the scene, and the closed mesh each lies on (-1:
    none): lamps other than suns, point emitters and emissive triangles' centres."""
    lamps = [light.position for light in scene.lights if light.kind != "SUN"]
    points = [np.reshape(np.asarray(lamps, dtype=np.float64), (-1, 3))]
    owners = [np.full(len(lamps), -1)]
    if scene.point_emitters is not None and len(scene.point_emitters):
        emitters = np.asarray(scene.point_emitters, dtype=np.float64)
        emitters = emitters[::max(1, -(-len(emitters) // INSIDE_TESTS))]
        points.append(emitters[:, :3])
        owners.append(np.full(len(emitters), -1))
    if scene.emission is not None:
        emissive = np.flatnonzero(np.asarray(scene.emission).max(axis=1) > 0.0)
        emissive = emissive[::max(1, -(-len(emissive) // INSIDE_TESTS))]
        points.append(np.asarray(scene.triangles, dtype=np.float64)[emissive].mean(axis=1))
        owners.append(pieces[emissive])
    return np.concatenate(points), np.concatenate(owners)


def _inside(point, corners):
    """Whether `point` lies inside the closed surface of triangles `corners` (m, 3, 3): a
    ray from it crosses the surface an odd number of times (Möller and Trumbore 1997)."""
    edge1, edge2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    p = np.cross(RAY, edge2)
    det = np.einsum("ij,ij->i", edge1, p)
    usable = np.abs(det) > 1e-30
    inverse = np.where(usable, 1.0 / np.where(usable, det, 1.0), 0.0)
    s = point - corners[:, 0]
    u = np.einsum("ij,ij->i", s, p) * inverse
    q = np.cross(s, edge1)
    v = (q @ RAY) * inverse
    t = np.einsum("ij,ij->i", edge2, q) * inverse
    hits = usable & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > 0.0)
    return bool(np.count_nonzero(hits) % 2)
