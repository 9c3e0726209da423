"""WDPM: fixed-point-iteration backward warping of dual paraboloid RSMs (METHOD §4).

The warp reads the distorted map and writes a corrected one of the same layout, plus a
per-texel status (background, converged, approximate, failed) and iteration count, and
the counts of both over the whole map (the numerical-stability figures).
"""
from dataclasses import dataclass, replace

import moderngl
import numpy as np

from .context import dispatch, set_uniforms
from .vpl import poisson_disk_points

STATUS_NAMES = ("background", "converged", "approximate", "failed")
MAX_ITERATIONS = 64
APPROXIMATE_FROM = 2  # eq. 7 from the third iteration: accepting more beat checking late (docs/method.md)


@dataclass
class WarpStatus:
    """Per-texel status image (status | restarted << 2 | iterations << 4) and the counts."""

    glc: object
    texture: moderngl.Texture
    counts: dict              # status name -> texels
    iteration_histogram: np.ndarray  # texels that stopped after k iterations, k = 0..64

    def read(self):
        """(status, restarted, iterations) arrays of the atlas, GL's bottom row first."""
        width, height = self.texture.size
        raw = np.frombuffer(self.texture.read(), dtype=np.int32).reshape(height, width)
        return raw & 3, (raw & 4) > 0, raw >> 4

    def release(self):
        self.glc.recycle(self.texture)


def reference_paraboloid_map(glc, cube, paraboloid):
    """The exact DPM that every DPM variant is measured against (thesis §6): `paraboloid`'s
    layout, each texel fetched from the cube map `cube` of the same light."""
    textures = [glc.texture(paraboloid.atlas_size, 4) for _ in range(3)]
    program = glc.compute("reference_dpm")
    for unit, texture in enumerate((cube.position, cube.normal, cube.flux)):
        texture.use(location=unit)
    for unit, texture in enumerate(textures):
        texture.bind_to_image(unit, read=False, write=True)
    for matrix, origin in zip(paraboloid.face_matrices, paraboloid.face_origins):
        set_uniforms(program, cube_position=0, cube_normal=1, cube_flux=2, hemisphere_view=matrix,
                     face_origin=tuple(int(v) for v in origin), resolution=paraboloid.resolution,
                     light_position=tuple(float(v) for v in paraboloid.light.position), **cube.lookup_uniforms())
        dispatch(program, paraboloid.resolution, paraboloid.resolution)
    return replace(paraboloid, position=textures[0], normal=textures[1], flux=textures[2])


def scarborough_tolerance(significant_figures):
    """Scarborough's criterion in percent: 0.5 x 10^(2 - n) (METHOD §4, eq. 7)."""
    return 0.5 * 10.0 ** (2 - significant_figures)


def warp_paraboloid_map(glc, rsm, alpha, iterations, significant_figures):
    """A corrected copy of a paraboloid RSM and its warp status."""
    gl = glc.gl
    textures = [glc.texture(rsm.atlas_size, 4) for _ in range(3)]
    status = glc.texture(rsm.atlas_size, 1, dtype="i4")
    counts = gl.buffer(reserve=(4 + MAX_ITERATIONS + 1) * 4)
    counts.clear()
    program = glc.compute("warp")
    for unit, texture in enumerate((rsm.position, rsm.normal, rsm.flux)):
        texture.use(location=unit)
    for unit, texture in enumerate((*textures, status)):
        texture.bind_to_image(unit, read=False, write=True)
    counts.bind_to_storage_buffer(0)
    pattern = np.ascontiguousarray(poisson_disk_points(8), dtype=np.float32)
    for matrix, origin in zip(rsm.face_matrices, rsm.face_origins):
        set_uniforms(program, source_position=0, source_normal=1, source_flux=2, hemisphere_view=matrix,
                     face_origin=tuple(int(v) for v in origin), resolution=rsm.resolution, alpha=float(alpha),
                     iterations=min(int(iterations), MAX_ITERATIONS),
                     scarborough_tolerance=scarborough_tolerance(significant_figures),
                     approximate_from=APPROXIMATE_FROM, restart_pattern=pattern)
        dispatch(program, rsm.resolution, rsm.resolution)
    totals = np.frombuffer(counts.read(), dtype=np.int32)
    counts.release()
    warped = replace(rsm, position=textures[0], normal=textures[1], flux=textures[2])
    return warped, WarpStatus(glc, status, dict(zip(STATUS_NAMES, map(int, totals[:4]))), totals[4:].copy())
