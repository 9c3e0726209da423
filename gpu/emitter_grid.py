"""The emitter grid (seed 002): the direct light of many point emitters (emissive
particles and instances, and the point lights beyond the light-map budget) through a
colour-sum and a direction-sum 3D texture, read at every pixel with trilinear, tricubic
or super-sampled interpolation; and the brute-force loop over every emitter that it is
measured against. The direction sum is kept as its positive and negative halves along
each axis (two textures): the irradiance of surfaces facing the axes, exact for them,
where the sum alone, one vector, misses light that comes from both sides.

The seed adds each emitter's light to the cells within a range cut where its light falls
below a threshold. Over a cloud of many weak emitters, cutting each one's range drops
most of the light (each shell of a uniform cloud gives as much as the last), so every
emitter here reaches every cell, through a hierarchy of clusters (shaders/
emitter_grid_build.comp): near cells see the finest clusters, far ones coarser clusters
(flux, flux-weighted position), about a thousand clusters a cell whatever the emitter
count. Emitters whose light at the view is negligible are skipped first, on the GPU
(`select`), as frame_lights.py skips lamps.
The grid heeds no occluders; gpu/emitter_shadows.py shades its light (docs/method.md).
"""
from dataclasses import dataclass

import moderngl
import numpy as np

from .closed_meshes import ROOM_CODE_DEFINES
from .colour import LUMINANCE_WEIGHTS
from .context import dispatch, dispatch_row, made_or_refused, set_uniforms, zero_buffer
from .settings import EMITTER_INTERPOLATIONS
from .scene import POINT_EMITTER_COLUMNS
from .shade import add_irradiance, bind_gbuffer
from .vpl import EMITTER_BYTES

CLUSTER_FLOATS = 8  # flux rgb, weight (r + g + b), weighted position xyz, weighted area
SKIP_BINS, BINS_PER_OCTAVE = 256, 4
"""The bins of the emitters' bounds at the view, from the strongest down 64 octaves (weaker
ones share the last): shaders/emitter_select.comp."""
SELECTION_WORDS = 13  # shaders/emitter_select.comp's Selection before its bins
SELECTION_START = np.concatenate([
    np.array([0, 0, 0], np.uint32), np.zeros(3, np.float32).view(np.uint32),
    np.full(3, 0xFFFFFFFF, np.uint32), np.zeros(3, np.uint32), np.zeros(1, np.uint32),
    np.zeros(SKIP_BINS, np.float32).view(np.uint32)]).tobytes()
"""The Selection buffer before a selection: no strongest bound, nothing kept, an empty box,
nothing dropped."""
BRUTE_FORCE_BATCH = 32768
"""Emitters one brute-force dispatch adds: llvmpipe ends a loop nest after 65,535 iterations."""


def float_from_order(keys):
    """The floats of shaders/emitter_select.comp's order_float keys."""
    keys = np.asarray(keys, dtype=np.uint32)
    return np.where(keys & 0x80000000, keys & 0x7FFFFFFF, ~keys).astype(np.uint32).view(np.float32)


@dataclass
class EmitterSelection:
    """What a frame keeps of the point emitters (the point lights beyond the budget always):
    how many, how many of the scene's are skipped (too weak at the view) and dropped (not
    finite, negative or without flux), the largest of the kept flux's channels (summed) and
    the kept positions' box (None when none is kept); `chosen` is what the selection was
    made for."""

    kept: int
    skipped: int
    dropped: int
    flux_bound: float
    box: tuple
    chosen: tuple

    @classmethod
    def read(cls, buffer, count, chosen):
        words = np.frombuffer(buffer.read(size=SELECTION_WORDS * 4), dtype=np.uint32)
        kept, dropped = int(words[2]), int(words[12])
        flux = words[3:6].view(np.float32)
        box = (float_from_order(words[6:9]), float_from_order(words[9:12])) if kept else None
        return cls(kept, count - kept - dropped, dropped, float(flux.max()) if kept else 0.0, box, chosen)

    def bounds(self, scene_bounds):
        """The scene's bounds grown to hold the kept emitters (which may lie outside it)."""
        if self.box is None:
            return scene_bounds
        return np.minimum(scene_bounds[0], self.box[0]), np.maximum(scene_bounds[1], self.box[1])


def grid_resolution(setting):
    """The cells along a side for the setting `emitter_grid_resolution`: the power of two
    at or above it, at least 8 (the cluster levels halve it down to 2)."""
    return 1 << max(3, int(setting - 1).bit_length())


GRID_TEXEL_BYTES = 16
"""An RGBA32F texel of the grid's textures."""


def largest_texture_side(settings):
    """Texels along a side of the largest texture the emitter grid of `settings` makes:
    the super-sampled read's are twice as fine as the grid."""
    side = grid_resolution(settings.emitter_grid_resolution)
    return 2 * side if settings.emitter_interpolation == "supersampled" else side


def _grid_textures(gl, resolution):
    """The colour sum and the direction sum's halves: three RGBA32F cubes of `resolution`
    texels a side, read with trilinear filtering, clamped at their edges; refused in one
    sentence where the driver cannot make them."""
    textures = made_or_refused(gl, lambda: tuple(gl.texture3d((resolution,) * 3, 4, dtype="f4") for _ in range(3)),
                               f"the emitter grid's {resolution}³ textures", "lower the emitter grid resolution")
    for texture in textures:
        texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
        texture.repeat_x = texture.repeat_y = texture.repeat_z = False
    return textures


def grid_box(box, resolution):
    """(origin, cell size) of a cube of `resolution` cells whose first and last cell
    centres lie on the faces of a cube around `box` (low, high), a hair larger: the walls
    of a room the box spans are read at cell centres, not from the centres half a cell
    inside (nearer the emitters)."""
    low, high = (np.asarray(corner, dtype=np.float64) for corner in box)
    side = max(float(np.max(high - low)), 1e-6) * 1.02
    cell = side / (resolution - 1)
    return (low + high) / 2 - side / 2 - cell / 2, cell


class EmitterGrid:
    """The clusters, textures and irradiance image of the emitter grid, made again only
    when the emitters, the box or the resolution change."""

    def __init__(self, glc, resolution):
        self.glc = glc
        self.resolution = resolution = grid_resolution(resolution)
        self.levels = int(np.log2(resolution))  # sizes resolution, resolution / 2, ..., 2
        sizes = [resolution >> level for level in range(self.levels)]
        self.offsets = np.concatenate([[0], np.cumsum([size ** 3 for size in sizes])[:-1]]).astype(np.int32)
        gl = glc.gl
        self.clusters = gl.buffer(reserve=int(sum(size ** 3 for size in sizes)) * CLUSTER_FLOATS * 4)
        self.textures = _grid_textures(gl, resolution)
        self.fine_textures = None  # twice as fine, for the super-sampled read: made on first use
        self.emitters = self._packed = None
        self._selected = gl.buffer(reserve=len(SELECTION_START))
        self.count = self.scene_count = 0
        self.selection = None  # the EmitterSelection of the last `select`
        self.irradiance = None
        self.origin, self.cell_size = np.zeros(3), 1.0
        self._key = self._built = None
        self._fine_built = False  # the build the fine textures were made from (False: none yet)

    def upload(self, emitters, lamps, key):
        """Take the scene's point emitters and the point lights beyond the map budget (each
        (M, 7) float32 as gpu/scene.py holds point emitters; None: none) unless `key` says
        they are the last ones, into the buffers of the last ones when they hold them."""
        if key == self._key and self.emitters is not None:
            return
        parts = [np.ascontiguousarray(rows, dtype=np.float32) for rows in (emitters, lamps) if rows is not None]
        self.scene_count = len(parts[0]) if emitters is not None else 0
        count = sum(len(rows) for rows in parts)
        if self.emitters is not None and self.emitters.size < max(count, 1) * EMITTER_BYTES:
            for buffer in (self.emitters, self._packed):
                buffer.release()
            self.emitters = None
        if self.emitters is None:
            self.emitters = self.glc.gl.buffer(reserve=max(count, 1) * EMITTER_BYTES)
            self._packed = self.glc.gl.buffer(reserve=max(count, 1) * POINT_EMITTER_COLUMNS * 4)
        self.glc.write(self._packed, [rows for rows in parts if len(rows)])
        self.count = count
        self._key = key
        self._built = self.selection = None

    def select(self, box, min_distance, cutoff):
        """Expand the rows into emitter rows on the GPU, the scene's emitters weakest at the
        view skipped and those of bad values dropped (shaders/emitter_select.comp: their
        bounds at the box `box` the camera sees, at least `min_distance` away; the weakest
        together under `cutoff` of their sum), and read back what is kept (an
        EmitterSelection; once per rows, box and cutoff)."""
        chosen = (self._key, tuple(map(tuple, box)), min_distance, cutoff)
        if self.selection is not None and self.selection.chosen == chosen:
            return self.selection
        self._selected.write(SELECTION_START)
        low, high = (tuple(float(v) for v in corner) for corner in box)
        uniforms = {"emitter_count": self.count, "scene_count": self.scene_count, "box_low": low, "box_high": high,
                    "min_distance_squared": float(min_distance) ** 2, "cutoff": float(cutoff),
                    "luminance_weights": tuple(LUMINANCE_WEIGHTS)}
        for binding, buffer in enumerate((self._packed, self.emitters, self._selected)):
            buffer.bind_to_storage_buffer(binding)
        for stage in range(4):
            program = self.glc.compute("emitter_select", STAGE=stage, POINT_EMITTER_COLUMNS=POINT_EMITTER_COLUMNS,
                                       SKIP_BINS=SKIP_BINS, BINS_PER_OCTAVE=BINS_PER_OCTAVE, **ROOM_CODE_DEFINES)
            if stage == 2:
                set_uniforms(program, cutoff=float(cutoff))
                dispatch(program, 1, local=(64,))
            elif self.count:
                dispatch_row(program, self.count, "first_emitter", **uniforms)
        self.selection = EmitterSelection.read(self._selected, self.count, chosen)
        self._built = None
        return self.selection

    def build(self, box, singularity_bound):
        """Cluster the selected emitters over the cube around `box` and fill the three
        textures (once per selection, box and bound)."""
        built = (self.selection.chosen, tuple(map(tuple, box)), singularity_bound)
        if self._built == built:
            return
        self.origin, self.cell_size = grid_box(box, self.resolution)
        zero_buffer(self.glc, self.clusters)
        grid = {"grid_origin": tuple(map(float, self.origin)), "cell_size": float(self.cell_size),
                "grid_size": self.resolution}
        if self.count:
            program = self.glc.compute("emitter_bin", CLUSTER_FLOATS=CLUSTER_FLOATS)
            self.emitters.bind_to_storage_buffer(0)
            self.clusters.bind_to_storage_buffer(1)
            set_uniforms(program, **grid)
            dispatch_row(program, self.count, "first_emitter", emitter_count=self.count)
            program = self.glc.compute("emitter_reduce", CLUSTER_FLOATS=CLUSTER_FLOATS)
            for level in range(1, self.levels):
                size = self.resolution >> level
                set_uniforms(program, fine_offset=int(self.offsets[level - 1]), coarse_offset=int(self.offsets[level]),
                             coarse_size=size)
                dispatch(program, size ** 3, local=(64,))
        program = self.glc.compute("emitter_grid_build", CLUSTER_FLOATS=CLUSTER_FLOATS, LEVELS=self.levels)
        self.clusters.bind_to_storage_buffer(1)
        for unit, texture in enumerate(self.textures):
            texture.bind_to_image(unit, read=False, write=True)
        set_uniforms(program, level_offsets=self.offsets, singularity_bound=singularity_bound,
                     luminance_weights=tuple(LUMINANCE_WEIGHTS), **grid)
        dispatch(program, self.resolution, self.resolution, self.resolution, local=(4, 4, 4))
        self._built = built

    def _image(self, size):
        if self.irradiance is None or self.irradiance.size != size:
            if self.irradiance is not None:
                self.irradiance.release()
            self.irradiance = self.glc.gl.texture(size, 4, dtype="f4")
        return self.irradiance

    def supersampled_textures(self):
        """The textures twice as fine whose trilinear read is the super-sampled read of the
        grid's (shaders/emitter_supersample.comp), made again once per build."""
        if self.fine_textures is None:
            self.fine_textures = _grid_textures(self.glc.gl, 2 * self.resolution)
        if self._fine_built != self._built:
            program = self.glc.compute("emitter_supersample")
            for unit, (texture, fine) in enumerate(zip(self.textures, self.fine_textures)):
                texture.use(location=unit)
                fine.bind_to_image(unit, read=False, write=True)
            set_uniforms(program, colour_sum=0, direction_positive=1, direction_negative=2, grid_size=self.resolution)
            dispatch(program, *(2 * self.resolution,) * 3, local=(4, 4, 4))
            self._fine_built = self._built
        return self.fine_textures

    def shade(self, targets, uniforms, interpolation):
        """Every pixel's irradiance from the grid into `irradiance`. `uniforms` are the
        G-buffer's, its textures bound."""
        image = self._image(targets.size)
        textures = self.supersampled_textures() if interpolation == "supersampled" else self.textures
        program = self.glc.compute("emitter_shade", INTERPOLATION=EMITTER_INTERPOLATIONS.index(interpolation))
        for unit, texture in enumerate(textures, start=2):
            texture.use(location=unit)
        image.bind_to_image(0, read=False, write=True)
        set_uniforms(program, **uniforms, colour_sum=2, direction_positive=3, direction_negative=4,
                     grid_origin=tuple(map(float, self.origin)), cell_size=float(self.cell_size),
                     grid_size=self.resolution, luminance_weights=tuple(LUMINANCE_WEIGHTS))
        dispatch(program, *targets.size)
        return image

    def brute_force(self, targets, uniforms, singularity_bound):
        """Every pixel's irradiance summed over every emitter into `irradiance`."""
        image = self._image(targets.size)
        program = self.glc.compute("emitter_brute")
        image.bind_to_image(0, read=True, write=True)
        set_uniforms(program, **uniforms, emitter_count=self.count, batch=BRUTE_FORCE_BATCH,
                     singularity_bound=singularity_bound)
        self.emitters.bind_to_storage_buffer(0)
        for first in range(0, max(self.count, 1), BRUTE_FORCE_BATCH):
            set_uniforms(program, first_emitter=first)
            dispatch(program, *targets.size)
        return image

    def add_light(self, targets, uniforms, settings, shadows=None):
        """Add albedo / π times the emitters' irradiance (from the grid, or by brute force
        as `settings.emitter_light` says; shaded by `shadows`, an EmitterShadows, when
        given) into the direct image."""
        bind_gbuffer(targets)
        if settings.emitter_light == "brute_force":
            image = self.brute_force(targets, uniforms, settings.singularity_bound)
        else:
            image = self.shade(targets, uniforms, settings.emitter_interpolation)
        if shadows is not None:
            shadows.apply(targets, uniforms, image)
        add_irradiance(self.glc, targets, uniforms, image)

    def resources(self):
        held = (self.clusters, *self.textures, *(self.fine_textures or ()), self._selected)
        return held + tuple(r for r in (self.emitters, self._packed, self.irradiance) if r is not None)

    def release(self):
        for resource in self.resources():
            resource.release()
