"""The indirect-light stage for each method: LPVs (the thesis's: inject VPLs, propagate)
or a light grid (gather every emitter's light at every cell centre), one per level and
phase, or VPL gathering (every pixel gathers, through the levels' occupancy); built from
the lights' VPLs and looked up by shaders/shade_indirect.comp."""
import math

import numpy as np

from .light_grid import LightGrid, cluster_levels
from .bounces import Bounces
from .emitter_bounce import light_receivers
from .lpv import LightPropagationVolume
from .occupancy import Occupancy
from .vpl_gather import VPLGather

INDIRECT_STAGES = {"lpv": ("inject_ms", "propagate_ms"), "light_grid": ("inject_ms", "gather_ms"),
                   "vpl_gather": ("inject_ms",)}
"""The timed stages of each method (stats keys) redone when the lights or the grids
change: for the light grid, voxelising the scene and clustering the emitters, then the
gather; for VPL gathering, voxelising (its gather follows the camera: pixel_gather_ms).
With more than one bounce, both light the VPLs by one another between them (bounce_ms)."""


class IndirectGrids:
    """The volumes of one method over `grids` (level-major, each level's `phases` grids
    together)."""

    def __init__(self, glc, method, grids, phases):
        self.glc = glc
        self.method = method
        self.grids = tuple(grids)
        self.levels = self.grids[::phases]
        self.bounces = Bounces(glc)
        self.emitter_sets = []  # what VPL gathering gathers from: (buffer, count) pairs
        self.emitter_vpls = None  # the emitters' bounce (gpu/emitter_bounce.py)
        self._lpv_occupancy = None  # what the emitters' bounce marches through with LPVs
        if method == "lpv":
            self.volumes = [LightPropagationVolume(glc, grid) for grid in self.grids]
        elif method == "light_grid":
            self.volumes = [LightGrid(glc, self.grids)]
        else:
            self.volumes = [VPLGather(glc, self.levels)]

    def build(self, maps, mesh, scene_bounds, settings, stats, pattern, sources=(), receivers=None):
        """Fill the grids from the lights' maps (pipeline.LightMaps), timing each stage;
        with `settings.bounces` above 1 (light grid and VPL gathering) from the VPLs lit by
        one another too (gpu/bounces.py), their senders' subsets following the VPL
        `pattern`; and from the emitter sets `sources` ((buffer, count) pairs) through the
        points `receivers()` gives (gpu/emitter_bounce.py)."""
        timed = self.glc.timed
        bound = settings.singularity_bound
        flux_bound = sum(m.vpl_map.flux_bound for m in maps)
        first, second = INDIRECT_STAGES[self.method][0], INDIRECT_STAGES[self.method][-1]
        if self.emitter_vpls is not None:
            self.emitter_vpls.release()
            self.emitter_vpls = None
        if self.method == "lpv":
            vpl_sets = [vpls for m in maps for vpls in (m.vpls, m.far_vpls) if vpls is not None]
            if sources:
                if self._lpv_occupancy is None:
                    self._lpv_occupancy = Occupancy(self.glc, self.levels)
                with timed(stats, "emitter_bounce_ms"):
                    self._lpv_occupancy.voxelise(mesh)
                    self.emitter_vpls = light_receivers(self.glc, receivers(), sources, self._lpv_occupancy,
                                                        range(len(self.levels)), bound, pattern)
                vpl_sets.append(self.emitter_vpls)
                flux_bound += self.emitter_vpls.flux_bound
            with timed(stats, first):
                for lpv in self.volumes:
                    lpv.inject(vpl_sets, flux_bound)
                    if settings.occlusion:
                        lpv.inject_geometry([m.vpl_map for m in maps])
            with timed(stats, second):
                for lpv in self.volumes:
                    lpv.propagate(settings.propagation_iterations, settings.occlusion)
            return
        volume = self.volumes[0]
        with timed(stats, first):
            volume.occupancy.voxelise(mesh)
        emitters = [emitter for m in maps for emitter in m.emitter_sets()]
        # the occupancy's grid of each level: a light grid's holds every phase, VPL gathering's the levels
        layers = range(0, len(self.grids), len(self.grids) // len(self.levels)) if self.method == "light_grid" \
            else range(len(self.levels))
        if settings.bounces > 1 and maps:
            with timed(stats, "bounce_ms"):
                emitters = self.bounces.build(maps, settings.bounces, volume.occupancy, layers, bound, pattern)
            emitters += [(m.far_vpls.buffer, m.far_vpls.count) for m in maps if m.far_vpls is not None]
            flux_bound *= settings.bounces  # a generation carries at most its area times what it receives
        else:
            self.bounces.release()
        if sources:
            with timed(stats, "emitter_bounce_ms"):
                self.emitter_vpls = light_receivers(self.glc, receivers(), sources, volume.occupancy, layers, bound,
                                                    pattern)
            emitters = emitters + [(self.emitter_vpls.buffer, self.emitter_vpls.count)]
            flux_bound += self.emitter_vpls.flux_bound
        if self.method == "vpl_gather":
            self.emitter_sets = emitters
            return
        with timed(stats, first):
            volume.cluster(emitters, flux_bound, cluster_levels(self.levels, scene_bounds))
        with timed(stats, second):
            volume.gather(bound)

    def forget(self):
        """Build everything again next time, the occupancy too."""
        for occupancy in (self.volumes[0].occupancy if self.method != "lpv" else None, self._lpv_occupancy):
            if occupancy is not None:
                occupancy.forget()

    def lookup_uniforms(self, first_unit):
        """Bind the volumes for the lookup from texture unit `first_unit` on; the uniforms
        that name them."""
        if self.method != "lpv":
            return self.volumes[0].lookup_uniforms(first_unit)
        uniforms = {}
        for channel, name in enumerate(("lpv_r", "lpv_g", "lpv_b")):
            units = first_unit + channel * len(self.volumes) + np.arange(len(self.volumes))
            for lpv, unit in zip(self.volumes, units):
                lpv.sums[channel].use(location=int(unit))
            uniforms[name] = units
        return uniforms

    def cell_light(self):
        """The light in each cell of the first grid, (x, y, z, rgb) float32, for the slice
        overlay: an LPV's ∫ I(ω) dω (the first SH coefficient times 2√π; the others
        integrate to zero), a light grid's mean irradiance over its six directions."""
        if self.method == "lpv":
            sums = [LightPropagationVolume.read(v)[..., 0] for v in self.volumes[0].sums]
            return (np.stack(sums, axis=-1) * 2 * math.sqrt(math.pi)).transpose(2, 1, 0, 3)
        if self.method == "light_grid":
            return self.volumes[0].read_irradiance(0).mean(axis=0).transpose(2, 1, 0, 3)
        return np.zeros((self.grids[0].size,) * 3 + (3,), dtype=np.float32)  # a gather holds no cells

    def resources(self):
        return (*(resource for volume in self.volumes for resource in volume.resources()),
                *self.bounces.resources(),
                *((self.emitter_vpls.buffer,) if self.emitter_vpls is not None else ()),
                *(self._lpv_occupancy.resources() if self._lpv_occupancy is not None else ()))

    def release(self):
        for volume in self.volumes:
            volume.release()
        self.bounces.release()
        for held in (self.emitter_vpls, self._lpv_occupancy):
            if held is not None:
                held.release()
