"""Virtual point lights sampled from an RSM by Poisson-disk cells (METHOD §6).

Each face of the atlas gets a Poisson-disk point set; every texel joins its nearest
point's cell, and the cell's VPL lies at one of its texels drawn in proportion to its
flux, carrying that texel's flux over the chance of drawing it: the VPLs' fluxes add up
to the RSM's in expectation, and no cell moves one surface's light onto another.
Pattern k > 0 is the same set moved by a random toroidal shift, so a still image that
averages the VPL sets of patterns 0, 1, 2, ... converges toward every texel's light.
Where surfaces have a glossy layer, a smaller set of glossy VPLs carries what the layers
reflect, each along the mirror direction of the light's ray (shaders/vpl_gather.comp).
"""
import math
from collections import OrderedDict
from dataclasses import dataclass
from functools import lru_cache

import moderngl
import numpy as np

from .closed_meshes import ROOM_CODE_DEFINES
from .context import dispatch, run_workgroups, set_uniforms
from .rsm import PROJECTION_PARABOLOID

EMITTER_BYTES = 3 * 16
"""A VPL's or any point emitter's bytes (shaders/emitter.glsl): position, normal, flux vec4s."""
SHARPEST_ALPHA = 0.09
"""The least GGX alpha of a glossy VPL's lobe (shaders/emitter.glsl glossy_lobe): half its
peak 6.6° off its axis. A mirror's would be a ray, which the light grid's cells and a set's
VPLs would catch on a few cells only (docs/method.md, "Glossy VPLs")."""


def glossy_blur_alpha(filter_glossy):
    """The GGX alpha Cycles' Filter Glossy (`filter_glossy`; 0: off) widens a glossy layer
    to, at least, where a path reaches it after a diffuse bounce: 0.5 sqrt(1 - pdf /
    filter_glossy) for the bounce's pdf, cos / pi, here at its mean over cosine-weighted
    directions, 2 / (3 pi). The light a glossy layer sends onto diffuse surfaces is such a
    path seen from the camera."""
    if filter_glossy <= 0.0:
        return 0.0
    return 0.5 * math.sqrt(max(1.0 - 2.0 / (3.0 * math.pi * filter_glossy), 0.0))


@lru_cache(maxsize=64)
def poisson_disk_points(count, in_disk=False, candidates=12, seed=20240607):
    """`count` points in [0, 1)^2 by Mitchell's best-candidate algorithm (a Poisson-disk set),
    or only inside the disk inscribed in it (a paraboloid map's valid region).

    Each new point is the candidate farthest from the points so far, found through a grid
    of buckets about one spacing wide, so a large set costs O(count) steps.
    """
    rng = np.random.default_rng(seed + count)
    grid = max(1, int(math.sqrt(count)))
    capacity = 8
    buckets = np.full((grid + 2, grid + 2, capacity, 2), np.nan)  # one empty ring around
    filled = np.zeros((grid + 2, grid + 2), dtype=np.int64)
    offsets = np.array([(dx, dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1)])
    points = np.empty((count, 2))
    for i in range(count):
        trial = rng.random((2 * candidates, 2))
        if in_disk:
            trial = trial[np.sum((2 * trial - 1) ** 2, axis=1) <= 1.0]
        trial = trial[:candidates]
        cells = (trial * grid).astype(np.int64) + 1
        around = cells[:, None, :] + offsets[None, :, :]
        near = buckets[around[..., 0], around[..., 1]]
        distance = np.sqrt(np.nansum((near - trial[:, None, None, :]) ** 2, axis=-1))
        distance[np.isnan(near[..., 0])] = np.inf
        best = trial[np.argmax(distance.min(axis=(1, 2)))]
        points[i] = best
        bx, by = (best * grid).astype(np.int64) + 1
        if filled[bx, by] < capacity:
            buckets[bx, by, filled[bx, by]] = best
            filled[bx, by] += 1
    return points.astype(np.float32)


def concentric_disk(square):
    """Shirley and Chiu's concentric map of [-1, 1]^2 onto the unit disk: it keeps area
    shares and bends distances little, so a Poisson set stays one."""
    a, b = square[:, 0], square[:, 1]
    first = np.abs(a) > np.abs(b)
    with np.errstate(divide="ignore", invalid="ignore"):
        radius = np.where(first, a, b)
        angle = np.where(first, np.pi / 4 * (b / a), np.pi / 2 - np.pi / 4 * (a / b))
    angle = np.where(radius == 0.0, 0.0, angle)
    return np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=1)


def concentric_square(disk):
    """The inverse of `concentric_disk`."""
    x, y = disk[:, 0], disk[:, 1]
    radius = np.hypot(x, y)
    angle = np.arctan2(y, x)
    angle = np.where(angle < -np.pi / 4, angle + 2 * np.pi, angle)
    octant = np.clip(np.floor((angle + np.pi / 4) / (np.pi / 2)), 0, 3)
    sign = np.where(octant < 2, 1.0, -1.0)
    t = (angle - octant * np.pi / 2) * 4 / np.pi  # in [-1, 1) along the square's side
    along_x = octant % 2 == 0
    a = np.where(along_x, sign * radius, -t * sign * radius)
    b = np.where(along_x, t * sign * radius, sign * radius)
    return np.stack([a, b], axis=1)


def shifted_pattern(points, in_disk, pattern):
    """Pattern `pattern` of a Poisson set in [0, 1)^2: pattern 0 is the set, another the
    set moved by a random toroidal shift (Cranley-Patterson rotation), over the square or,
    for a set in the inscribed disk, over the square the disk maps to concentrically.
    Every point of a shifted set lies anywhere with equal probability, the set keeps its
    spacing, and a paraboloid map's set stays in its disk."""
    if pattern == 0:
        return points
    shift = np.random.default_rng(pattern).random(2)
    if not in_disk:
        return ((points + shift) % 1.0).astype(np.float32)
    square = concentric_square(2.0 * points.astype(np.float64) - 1.0)
    moved = (square + 1.0 + 2.0 * shift) % 2.0 - 1.0
    return (0.5 + 0.5 * concentric_disk(moved)).astype(np.float32)


@dataclass
class VPLSet:
    """The VPLs of one light in a GPU buffer: per VPL position (w: 1 + its room, valid
    where above 0), normal (a glossy VPL's: its lobe's axis; w surfel area), flux (rgb; w
    a glossy VPL's lobe alpha, negated, else 0) as three vec4."""

    buffer: moderngl.Buffer
    count: int

    def read(self):
        data = np.frombuffer(self.buffer.read(), dtype=np.float32).reshape(self.count, 3, 4)
        return {"position": data[:, 0, :3], "valid": data[:, 0, 3] > 0, "room": data[:, 0, 3] - 1,
                "normal": data[:, 1, :3], "area": data[:, 1, 3], "flux": data[:, 2, :3], "lobe": -data[:, 2, 3]}

    def release(self):
        self.buffer.release()


LAID_OUT = OrderedDict()
"""The cells of pattern 0 of the layouts made last in this process, as bytes (cell ids,
bounds, sample points) by layout: a new pipeline's first VPL set (a batch render's next
frame, a benchmark's next case) uploads them instead of assigning every texel again. The
later patterns of converging sets are assigned anew: reading each back cost more than
assigning it (its cell ids are a GPU-stalling read of the whole atlas)."""
LAID_OUT_KEPT = 8


class PoissonCells:
    """Which texel belongs to which VPL's cell, for one atlas layout, VPL count and pattern."""

    def __init__(self, glc, atlas_size, face_origins, resolution, vpl_count, in_disk, pattern=0):
        gl = glc.gl
        faces = len(face_origins)
        per_face = [vpl_count // faces + (f < vpl_count % faces) for f in range(faces)]
        self.count = sum(per_face)
        key = (tuple(atlas_size), tuple(map(tuple, np.asarray(face_origins).tolist())), resolution, vpl_count, in_disk)
        self.cell_ids = gl.texture(atlas_size, 1, dtype="i4")
        self.cell_ids.filter = (moderngl.NEAREST, moderngl.NEAREST)
        if pattern == 0 and key in LAID_OUT:
            LAID_OUT.move_to_end(key)
            cell_ids, bounds, samples = LAID_OUT[key]
            self.cell_ids.write(cell_ids)
            self.bounds, self.samples = gl.buffer(bounds), gl.buffer(samples)
            return
        self._assign(glc, face_origins, resolution, per_face, in_disk, pattern)
        if pattern == 0:
            gl.memory_barrier()
            LAID_OUT[key] = (self.cell_ids.read(), self.bounds.read(), self.samples.read())
            while len(LAID_OUT) > LAID_OUT_KEPT:
                LAID_OUT.popitem(last=False)

    def _assign(self, glc, face_origins, resolution, per_face, in_disk, pattern):
        gl = glc.gl
        bounds = np.tile(np.array([2 ** 30, 2 ** 30, -1, -1], dtype=np.int32), (self.count, 1))
        self.bounds = gl.buffer(bounds.tobytes())
        samples = []
        program = glc.compute("vpl_assign")
        self.cell_ids.bind_to_image(0, read=False, write=True)
        self.bounds.bind_to_storage_buffer(2)
        first = 0
        for origin, n in zip(face_origins, per_face):
            if n == 0:
                continue
            grid = max(1, int(math.sqrt(n)))
            points = shifted_pattern(poisson_disk_points(n, in_disk), in_disk, pattern)
            bucket = np.minimum((points * grid).astype(np.int64), grid - 1)
            order = np.argsort(bucket[:, 1] * grid + bucket[:, 0], kind="stable")
            points = points[order]
            keys = (bucket[order, 1] * grid + bucket[order, 0])
            starts = np.searchsorted(keys, np.arange(grid * grid + 1)).astype(np.int32)
            point_buffer = gl.buffer(points.tobytes())
            start_buffer = gl.buffer(starts.tobytes())
            point_buffer.bind_to_storage_buffer(0)
            start_buffer.bind_to_storage_buffer(1)
            set_uniforms(program, face_origin=tuple(int(v) for v in origin), resolution=resolution,
                         first_cell=first, point_count=n, grid=grid)
            dispatch(program, resolution, resolution)
            point_buffer.release()
            start_buffer.release()
            samples.append(origin[None, :] + points * resolution)
            first += n
        self.samples = gl.buffer(np.concatenate(samples).astype(np.float32).tobytes())

    def resources(self):
        return (self.cell_ids, self.bounds, self.samples)

    def release(self):
        for resource in self.resources():
            resource.release()


class VPLSampler:
    """Samples VPLs from RSMs, keeping the Poisson cells of each atlas layout for the
    pattern it was last asked for."""

    def __init__(self, glc):
        self.glc = glc
        self._cells = {}  # layout -> (pattern, PoissonCells)

    def cells(self, rsm, vpl_count, pattern=0):
        in_disk = rsm.projection_kind == PROJECTION_PARABOLOID
        key = (rsm.atlas_size, rsm.resolution, rsm.face_count, vpl_count, in_disk)
        held = self._cells.get(key)
        if held is None or held[0] != pattern:
            if held is not None:
                held[1].release()
            held = self._cells[key] = (pattern, PoissonCells(self.glc, rsm.atlas_size, rsm.face_origins,
                                                             rsm.resolution, vpl_count, in_disk, pattern))
        return held[1]

    def resources(self):
        """The GPU resources of every cached Poisson cell layout."""
        return tuple(resource for _, cells in self._cells.values() for resource in cells.resources())

    def sample(self, rsm, vpl_count, pattern=0, exclude=None, room=0, glossy=False, least_alpha=0.0):
        """The VPLs of `rsm`'s cells in Poisson pattern `pattern`, leaving out the texels
        whose surface lies in the box `exclude` ((low, high) corners) when given, each in
        the light's `room` (gpu/closed_meshes.py); with `glossy`, of the light its surfaces'
        glossy layers reflect, their lobes of GGX alpha at least `least_alpha`, else of the rest.
        Glossy VPLs keep pattern 0's cells and draw their texels anew in each pattern: over
        sets they still converge toward every texel's light, without a second layout
        assigned each set."""
        cells = self.cells(rsm, vpl_count, 0 if glossy else pattern)
        program = self.glc.compute("vpl_gather", SHARPEST_ALPHA=SHARPEST_ALPHA, **ROOM_CODE_DEFINES)
        output = self.glc.gl.buffer(reserve=cells.count * EMITTER_BYTES)
        for unit, texture in enumerate((rsm.position, rsm.normal, rsm.flux, cells.cell_ids)):
            texture.use(location=unit)
        low, high = exclude if exclude is not None else ((0.0,) * 3, (0.0,) * 3)
        set_uniforms(program, rsm_position=0, rsm_normal=1, rsm_flux=2, cell_ids=3, cell_count=cells.count,
                     exclude=exclude is not None, exclude_low=tuple(low), exclude_high=tuple(high),
                     pattern=pattern, room=room, glossy=glossy, least_alpha=least_alpha, **rsm.light_uniforms)
        cells.samples.bind_to_storage_buffer(0)
        cells.bounds.bind_to_storage_buffer(1)
        output.bind_to_storage_buffer(2)
        run_workgroups(program, cells.count)
        return VPLSet(output, cells.count)

    def release(self):
        for _, cells in self._cells.values():
            cells.release()
        self._cells.clear()
