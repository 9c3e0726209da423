"""The light propagation volume: injection, geometry volume, propagation (METHOD §7).

Cell contents are 2-band SH of radiant intensity (W/sr) per colour channel, in three
RGBA float volumes (one per channel, the four coefficients in RGBA).
"""
import math

import moderngl
import numpy as np

from .context import dispatch, set_uniforms, zero_buffer

SH_C0 = 1 / (2 * math.sqrt(math.pi))
SH_C1 = math.sqrt(3 / (4 * math.pi))
LOBE_C0 = math.sqrt(math.pi) / 2
LOBE_C1 = math.sqrt(math.pi / 3)
FAR_FACE_SOLID_ANGLE = 0.4006696846
SIDE_FACE_SOLID_ANGLE = 0.4234313544
LPV_FIXED_POINT_RANGE = 2.0 ** 30   # the largest total a channel may reach in the integers
GEOMETRY_FIXED_POINT_SCALE = 2.0 ** 20
VOLUME_LOCAL = (4, 4, 4)
LPV_BYTES_PER_CELL = 12 * 4 + 9 * 16
"""The injection's integer accumulator (12 channels) and the ping, pong and sum volumes
(three RGBA32F volumes each, one per colour)."""
GEOMETRY_VOLUME_BYTES_PER_CELL = 16 + 16  # its accumulator and its volume, one cell larger a side


def sh_basis(w):
    """The SH basis [Y00, Y1-1, Y10, Y11] at unit directions w (..., 3), float64."""
    w = np.asarray(w, dtype=np.float64)
    return np.stack([np.full(w.shape[:-1], SH_C0), -SH_C1 * w[..., 1], SH_C1 * w[..., 2], -SH_C1 * w[..., 0]], -1)


def cos_lobe(n):
    """SH projection of the clamped cosine max(0, n.w), float64."""
    n = np.asarray(n, dtype=np.float64)
    return np.stack([np.full(n.shape[:-1], LOBE_C0), -LOBE_C1 * n[..., 1], LOBE_C1 * n[..., 2], -LOBE_C1 * n[..., 0]], -1)


GEOMETRY_TEXELS_PER_CELL = 2
"""About how many map texels along a grid cell's side the geometry volume samples."""


def geometry_stride(map_resolution, grid_size):
    """The block of map texels one texel stands for in the geometry volume: a map face
    spans about as many cells as the grid, so keep GEOMETRY_TEXELS_PER_CELL a cell."""
    return max(1, map_resolution // (GEOMETRY_TEXELS_PER_CELL * grid_size))


def volume_textures(gl, size, count):
    textures = []
    for _ in range(count):
        texture = gl.texture3d((size, size, size), 4, dtype="f4")
        texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
        texture.repeat_x = texture.repeat_y = texture.repeat_z = False
        textures.append(texture)
    return textures


class LightPropagationVolume:
    """Inject VPLs and RSM surfels, then propagate; `sums` holds the propagated light."""

    def __init__(self, glc, grid):
        self.glc = glc
        self.grid = grid
        gl = glc.gl
        n = grid.size
        self.accumulator = gl.buffer(reserve=n ** 3 * 12 * 4)
        self.geometry_accumulator = gl.buffer(reserve=(n + 1) ** 3 * 4 * 4)
        self.ping = volume_textures(gl, n, 3)
        self.pong = volume_textures(gl, n, 3)
        self.sums = volume_textures(gl, n, 3)
        self.geometry = volume_textures(gl, n + 1, 1)[0]
        self.fixed_point_scale = 1.0

    def _grid_uniforms(self):
        return {"grid_origin": self.grid.origin, "cell_size": self.grid.cell_size, "grid_size": self.grid.size}

    def inject(self, vpl_sets, flux_bound):
        """Add every VPL's (flux/pi)·cosLobe(n) into its cell (integer atomics).

        `flux_bound` bounds any channel's total flux, so the fixed-point sums cannot overflow.
        """
        largest = flux_bound / math.pi * LOBE_C1 * 1.5  # a glossy lobe's (lpv_inject.comp)
        self.fixed_point_scale = LPV_FIXED_POINT_RANGE / largest if largest > 0 else 1.0
        zero_buffer(self.glc, self.accumulator)
        program = self.glc.compute("lpv_inject")
        self.accumulator.bind_to_storage_buffer(1)
        for vpls in vpl_sets:
            vpls.buffer.bind_to_storage_buffer(0)
            set_uniforms(program, vpl_count=vpls.count, fixed_point_scale=self.fixed_point_scale,
                         **self._grid_uniforms())
            dispatch(program, vpls.count, local=(64,))
        # The sums start from the injected light, as in the paper: propagation adds to it.
        self._resolve(self.accumulator, self.ping, 1.0 / self.fixed_point_scale)
        self._resolve(self.accumulator, self.sums, 1.0 / self.fixed_point_scale)

    def inject_geometry(self, rsms):
        """Add the RSM surfels' blocking potential into the geometry volume: one texel of
        every block of geometry_stride² stands for it."""
        zero_buffer(self.glc, self.geometry_accumulator)
        program = self.glc.compute("geometry_inject")
        self.geometry_accumulator.bind_to_storage_buffer(0)
        for rsm in rsms:
            rsm.position.use(location=0)
            rsm.normal.use(location=1)
            stride = geometry_stride(rsm.resolution, self.grid.size)
            set_uniforms(program, rsm_position=0, rsm_normal=1, atlas_size=rsm.atlas_size, stride=stride,
                         fixed_point_scale=GEOMETRY_FIXED_POINT_SCALE, **self._grid_uniforms())
            dispatch(program, *(-(-side // stride) for side in rsm.atlas_size))
        self._resolve(self.geometry_accumulator, [self.geometry], 1.0 / GEOMETRY_FIXED_POINT_SCALE)

    def _resolve(self, accumulator, volumes, inverse_scale):
        program = self.glc.compute("lpv_resolve", CHANNELS=len(volumes))
        accumulator.bind_to_storage_buffer(0)
        for unit, volume in enumerate(volumes):
            volume.bind_to_image(unit, read=False, write=True)
        size = volumes[0].size[0]
        set_uniforms(program, size=size, inverse_scale=inverse_scale)
        dispatch(program, size, size, size, local=VOLUME_LOCAL)

    def propagate(self, iterations, occlusion):
        """Ping-pong propagation steps, each added into `sums`; occlusion from step two on.
        Each step first scales its source cells so it sends out no more light than they
        hold (shaders/lpv_conserve.comp)."""
        program = self.glc.compute("lpv_propagate")
        source, target = self.ping, self.pong
        n = self.grid.size
        conserve = self.glc.compute("lpv_conserve")
        for step in range(iterations):
            for unit, volume in enumerate(source):
                volume.bind_to_image(unit, read=True, write=True)
            set_uniforms(conserve, grid_size=n)
            dispatch(conserve, n, n, n, local=VOLUME_LOCAL)
            for unit, volume in enumerate(source):
                volume.use(location=unit)
            self.geometry.use(location=3)
            for unit, volume in enumerate(target):
                volume.bind_to_image(unit, read=False, write=True)
            for unit, volume in enumerate(self.sums):
                volume.bind_to_image(3 + unit, read=True, write=True)
            set_uniforms(program, source_r=0, source_g=1, source_b=2, geometry_volume=3, grid_size=n,
                         use_occlusion=bool(occlusion and step > 0))
            dispatch(program, n, n, n, local=VOLUME_LOCAL)
            source, target = target, source

    @staticmethod
    def read(volume):
        """A volume as a (z, y, x, 4) float32 array."""
        nx, ny, nz = volume.size
        return np.frombuffer(volume.read(), dtype=np.float32).reshape(nz, ny, nx, 4)

    def resources(self):
        """Every GPU buffer and volume the LPV holds."""
        return (self.accumulator, self.geometry_accumulator, self.geometry, *self.ping, *self.pong, *self.sums)

    def release(self):
        for resource in self.resources():
            resource.release()
