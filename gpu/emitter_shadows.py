"""The point emitters' shadows: the emitter grid heeds no occluders, so a light grid
(gpu/light_grid.py, the indirect stage's machinery fed the emitters instead of VPLs,
over the same grids, with an occupancy of its own) gathers the emitters at its cell
centres both through the occupancy and without it, and every pixel's emitter
light is scaled by the ratio of the two looked up there (shaders/emitter_visibility.comp):
particles in a closed box light nothing outside it, and a wall shades the room behind.
The ratio is smooth at the cells' scale: shadows sharper than a cell are lost."""
import numpy as np

from .colour import LUMINANCE_WEIGHTS
from .context import dispatch, set_uniforms
from .light_grid import LightGrid, cluster_levels


class EmitterShadows:
    """The light grid of the emitters over the frame's indirect grids."""

    def __init__(self, glc, grids, phases):
        self.glc = glc
        self.grids = tuple(grids)
        self.phases = phases
        self.light_grid = LightGrid(glc, self.grids, unshadowed=True)
        self._built = None

    def build(self, mesh, emitter_sets, flux_bound, scene_bounds, singularity_bound, key):
        """Gather the emitters (buffers with counts) into the grids, once per `key`."""
        if self._built == key:
            return
        self.light_grid.occupancy.voxelise(mesh)
        self.light_grid.cluster(emitter_sets, flux_bound, cluster_levels(self.grids[::self.phases], scene_bounds))
        self.light_grid.gather(singularity_bound, range(0, len(self.grids), self.phases))
        self._built = key

    def apply(self, targets, uniforms, irradiance):
        """Scale the emitters' `irradiance` image by the share that reaches each pixel.
        `uniforms` are the G-buffer's, its textures bound."""
        grids = {"grid_origins": np.array([grid.origin for grid in self.grids]),
                 "cell_sizes": np.array([grid.cell_size for grid in self.grids]), "grid_size": self.grids[0].size,
                 "luminance_weights": tuple(LUMINANCE_WEIGHTS)}
        irradiance.bind_to_image(0, read=True, write=True)
        program = self.glc.compute("emitter_visibility", LEVELS=len(self.grids) // self.phases, PHASES=self.phases)
        set_uniforms(program, **uniforms, **self.light_grid.lookup_uniforms(first_unit=2, paired=True), **grids)
        dispatch(program, *targets.size)

    def resources(self):
        return self.light_grid.resources()

    def release(self):
        self.light_grid.release()
