"""The indirect-light stage, one class per method of gpu/settings.py INDIRECT_METHODS: LPVs
(the thesis's: inject VPLs, propagate), a light grid (gather every emitter's light at
every cell centre), one per level and phase, or VPL gathering (every pixel gathers,
through the levels' occupancy); built from the lights' VPLs and looked up by
shaders/shade_indirect.comp. The pipeline and gpu/capacity.py ask the method's object
(or class) what differs, never its name."""
import math

import numpy as np

from .bounces import Generations, conserve, light_bounces
from .emitter_bounce import RECEIVER_BYTES, EmitterSources, light_receivers
from .light_grid import DIRECTIONS, LIGHT_GRID_BYTES_PER_CELL, LightGrid, cluster_bytes, cluster_levels
from .lpv import GEOMETRY_VOLUME_BYTES_PER_CELL, LPV_BYTES_PER_CELL, LightPropagationVolume
from .occupancy import GATHER_VOXELS_PER_CELL, LARGE_TRIANGLE_BYTES, VOXELS_PER_CELL, occupancy_bytes
from .settings import INDIRECT_METHODS
from .vpl import EMITTER_BYTES
from .vpl_gather import VPLGather, pixel_gather_bytes


class IndirectMethod:
    """The volumes of one method over `grids` (level-major, each level's `phases` grids
    together), what builds them from the lights' VPLs and what looks them up."""

    name = None
    """Its name in gpu/settings.py INDIRECT_METHODS."""
    stages = ()
    """The timed stages (stats keys) a build redoes when the lights or the grids change.
    With more than one bounce, the gathering methods gather later generations of the
    light too, lit on points of the surfaces (gpu/bounces.py; bounce_ms)."""
    gathers_per_pixel = False
    """Whether every pixel gathers after the G-buffer (gather_pixels, pixel_gather_ms)."""
    more_bounces = False
    """Whether it carries bounces after the first (gpu/bounces.py)."""

    def __init__(self, glc, grids, phases):
        self.glc = glc
        self.grids = tuple(grids)
        self.levels = self.grids[::phases]
        self.generations = Generations(glc)
        self.emitter_vpls = None  # the emitters' bounce (gpu/emitter_bounce.py)
        self.volumes = self._volumes()
        self._pixel_gather = None  # made when a frame has emitters (pixel_gather)

    def _volumes(self):
        """Its volumes over the grids, made once."""
        raise NotImplementedError

    @staticmethod
    def key(settings):
        """The settings its content depends on beyond those of every method."""
        return ()

    @staticmethod
    def needed_bytes(settings, scene, pixels, mapped):
        """GPU bytes its volumes need for `scene` at `pixels` pixels with `mapped` lights
        that have maps, before anything is allocated (gpu/capacity.py)."""
        raise NotImplementedError

    @staticmethod
    def longest_side(settings):
        """The longest side, in texels, of a volume it allocates."""
        raise NotImplementedError

    def build(self, maps, mesh, scene_bounds, settings, stats, pattern, sources=EmitterSources(), receivers=None,
              rooms=None):
        """Fill the grids from the lights' maps (gpu/light_maps.py LightMaps), timing each
        stage; from the emitters `sources` (gpu/emitter_bounce.py EmitterSources) through points drawn
        on the surfaces by `receivers()` (the scene's gpu/emitter_bounce.py Receivers, made
        on first use); and with `settings.bounces` above 1 (gathering methods) from the
        later generations (gpu/bounces.py), on points it draws too, their senders' subsets
        following the VPL `pattern`. With `rooms` (gpu/closed_meshes.py Rooms) a light grid
        keeps each room's light in its cells (the VPLs carry their rooms themselves)."""
        if self.emitter_vpls is not None:
            self.emitter_vpls.release()
            self.emitter_vpls = None
        self._build(maps, mesh, scene_bounds, settings, stats, pattern, sources, receivers, rooms,
                    sum(m.flux_bound for m in maps))

    def _build(self, maps, mesh, scene_bounds, settings, stats, pattern, sources, receivers, rooms, flux_bound):
        raise NotImplementedError

    def gather_pixels(self, targets, uniforms, camera_position, singularity_bound, pattern, held_bound,
                      room_sides=None):
        """Gather every pixel's light (gathers_per_pixel), the VPLs' 1/r² bounded by
        `singularity_bound`, the held bound of the later bounces' by `held_bound`, with
        `room_sides` (the mesh's sides-and-rooms buffer) each from its own room's alone;
        `uniforms` are the G-buffer's, its textures bound."""

    def cell_rooms(self):
        """The texture of its cells' rooms (gpu/light_grid.py mark_cells) where the last
        build kept rooms apart in cells, else None."""
        return None

    def pixel_gather(self):
        """The pixel gather (gpu/vpl_gather.py) that adds the emitters' direct light (the
        emissive surfaces' and the world's: gpu/surface_emitters.py) and whose occupancy,
        six voxels a cell, the emitters' bounce marches: a light through a window passes a
        frame thickened by half a voxel on each side, so the light grid's three voxels a
        cell would narrow it twice as much (docs/method.md, "The emitters' bounce")."""
        if self._pixel_gather is None:
            self._pixel_gather = VPLGather(self.glc, self.levels)
        return self._pixel_gather

    def _bounce_occupancy(self, mesh):
        """The occupancy every bounce on points of the surfaces marches, whatever the method:
        the pixel gather's, voxelised (docs/method.md, "The emitters' bounce")."""
        occupancy = self.pixel_gather().occupancy
        occupancy.voxelise(mesh)
        return occupancy

    def _bounce_emitters(self, mesh, settings, stats, pattern, sources, receivers):
        """The emitters' bounce: the light of `sources` (gpu/emitter_bounce.py
        EmitterSources) on points `receivers()` draws, marched through the pixel gather's
        occupancy and held on the GPU to at most their flux times the largest albedo of the
        surfaces (gpu/bounces.py conserve), so its flux bound is known without waiting for
        the GPU; returns that bound."""
        with self.glc.timed(stats, "emitter_bounce_ms"):
            receiving = receivers()
            points = receiving.draw(settings.emitter_bounce_samples, pattern)
            albedo = receiving.largest_albedo
            self.emitter_vpls = light_receivers(self.glc, points, sources.sets, self._bounce_occupancy(mesh),
                                                settings.singularity_bound, pattern,
                                                sources.flux_bound * float(np.max(albedo)))
            conserve(self.glc, self.generations.sums(), self.emitter_vpls, sources.sets, albedo, sources.flux_bound)
        return self.emitter_vpls.flux_bound

    def forget(self):
        """Build everything again next time, the occupancy too."""
        if self._pixel_gather is not None:
            self._pixel_gather.occupancy.forget()

    def lookup_uniforms(self, first_unit):
        """Bind the volumes for the lookup from texture unit `first_unit` on; the uniforms
        that name them."""
        return self.volumes[0].lookup_uniforms(first_unit)

    def march_occupancy(self):
        """The voxelised occupancy a reflected ray is marched through, with its levels'
        layers (finest first); None where the method holds none."""
        gather = self._pixel_gather
        if gather is None or gather.occupancy.voxelised is None:
            return None
        return gather.occupancy, gather.occupancy.every_grid_layers()

    def cell_light(self):
        """The light in each cell of the first grid, (x, y, z, rgb) float32, for the slice
        overlay (gpu/debug_views.py)."""
        return np.zeros((self.grids[0].size,) * 3 + (3,), dtype=np.float32)  # a gather holds no cells

    def statistics(self, settings):
        """The frame's statistics about the indirect stage."""
        return {"indirect_method": self.name, "lpv_resolution": settings.lpv_resolution,
                "lpv_cell_size": self.grids[0].cell_size, "grid_levels": len(self.levels),
                "propagation_iterations": settings.propagation_iterations}

    def _held(self):
        return (self._pixel_gather,) if self._pixel_gather is not None else ()

    def resources(self):
        return (*(resource for volume in self.volumes for resource in volume.resources()),
                *self.generations.resources(),
                *((self.emitter_vpls.buffer,) if self.emitter_vpls is not None else ()),
                *(resource for held in self._held() for resource in held.resources()))

    def release(self):
        for volume in self.volumes:
            volume.release()
        self.generations.release()
        for held in (self.emitter_vpls, *self._held()):
            if held is not None:
                held.release()


class LPVMethod(IndirectMethod):
    """Light propagation volumes, one a grid: the VPLs injected, then propagated."""

    name = "lpv"
    stages = ("inject_ms", "propagate_ms")

    def _volumes(self):
        return [LightPropagationVolume(self.glc, grid) for grid in self.grids]

    @staticmethod
    def needed_bytes(settings, scene, pixels, mapped):
        n = settings.lpv_resolution
        return settings.grid_levels * settings.grid_phases * (
            n ** 3 * LPV_BYTES_PER_CELL + (n + 1) ** 3 * GEOMETRY_VOLUME_BYTES_PER_CELL)

    @staticmethod
    def longest_side(settings):
        return settings.lpv_resolution + 1  # the geometry volume

    def _build(self, maps, mesh, scene_bounds, settings, stats, pattern, sources, receivers, rooms, flux_bound):
        vpl_sets = [vpls for m in maps for vpls in m.vpl_sets()]
        if sources:
            flux_bound += self._bounce_emitters(mesh, settings, stats, pattern, sources, receivers)
            vpl_sets.append(self.emitter_vpls)
        with self.glc.timed(stats, "inject_ms"):
            for lpv in self.volumes:
                lpv.inject(vpl_sets, flux_bound)
                if settings.occlusion:
                    lpv.inject_geometry([m.vpl_map for m in maps])
        with self.glc.timed(stats, "propagate_ms"):
            for lpv in self.volumes:
                lpv.propagate(settings.propagation_iterations, settings.occlusion)

    def lookup_uniforms(self, first_unit):
        uniforms = {}
        for channel, name in enumerate(("lpv_r", "lpv_g", "lpv_b")):
            units = first_unit + channel * len(self.volumes) + np.arange(len(self.volumes))
            for lpv, unit in zip(self.volumes, units):
                lpv.sums[channel].use(location=int(unit))
            uniforms[name] = units
        return uniforms

    def cell_light(self):
        """An LPV's ∫ I(ω) dω: the first SH coefficient times 2√π (the others integrate
        to zero)."""
        sums = [LightPropagationVolume.read(v)[..., 0] for v in self.volumes[0].sums]
        return (np.stack(sums, axis=-1) * 2 * math.sqrt(math.pi)).transpose(2, 1, 0, 3)


class GatheringMethod(IndirectMethod):
    """A method that gathers every emitter's light with visibility through an occupancy
    of the scene, so later bounces may first be lit on points of the surfaces
    (gpu/bounces.py)."""

    more_bounces = True

    @staticmethod
    def key(settings):
        return settings.singularity_bound, settings.bounces, settings.emitter_bounce_samples * (settings.bounces > 1)

    @staticmethod
    def bounce_bytes(settings, scene):
        """The later generations' points (gpu/bounces.py)."""
        return max(light_bounces(settings, scene) - 1, 0) * settings.emitter_bounce_samples * RECEIVER_BYTES

    def _layers(self):
        """The occupancy's grid of each level."""
        raise NotImplementedError

    def _gathered_emitters(self, maps, mesh, settings, stats, pattern, sources, receivers, flux_bound):
        """The occupancy voxelised, the (buffer, count) sets to gather from (the VPLs, the
        emitters' bounce and, with more bounces, the later generations) and their flux
        bound."""
        occupancy = self.volumes[0].occupancy
        with self.glc.timed(stats, self.stages[0]):
            occupancy.voxelise(mesh)
        emitters = [emitter for m in maps for emitter in m.emitter_sets()]
        if sources:
            flux_bound += self._bounce_emitters(mesh, settings, stats, pattern, sources, receivers)
            emitters = emitters + [(self.emitter_vpls.buffer, self.emitter_vpls.count)]
        if settings.bounces > 1 and emitters:
            with self.glc.timed(stats, "bounce_ms"):
                emitters = emitters + self.generations.build(emitters, flux_bound, settings.bounces, receivers(),
                                                             settings.emitter_bounce_samples,
                                                             self._bounce_occupancy(mesh),
                                                             settings.singularity_bound, pattern)
            flux_bound += self.generations.flux_bound
        else:
            self.generations.drop()
        return emitters, flux_bound

    def forget(self):
        super().forget()
        self.volumes[0].occupancy.forget()

    def march_occupancy(self):
        occupancy = self.volumes[0].occupancy
        return (occupancy, tuple(self._layers())) if occupancy.voxelised is not None else None


class LightGridMethod(GatheringMethod):
    """A light grid over every grid: the emitters clustered, then every cell centre
    gathers their light (inject_ms: voxelising and clustering; gather_ms)."""

    name = "light_grid"
    stages = ("inject_ms", "gather_ms")

    def __init__(self, glc, grids, phases):
        self._rooms_apart = False  # whether the last build kept rooms apart in its cells
        super().__init__(glc, grids, phases)

    def _volumes(self):
        return [LightGrid(self.glc, self.grids)]

    @classmethod
    def needed_bytes(cls, settings, scene, pixels, mapped):
        s, n = settings, settings.lpv_resolution
        return (s.grid_levels * s.grid_phases * n ** 3 * LIGHT_GRID_BYTES_PER_CELL
                + occupancy_bytes(s.grid_levels * s.grid_phases, n, VOXELS_PER_CELL)
                + scene.triangle_count * LARGE_TRIANGLE_BYTES
                + cluster_bytes(s.vpls_per_light * mapped, s)
                + cls.bounce_bytes(s, scene))

    @staticmethod
    def longest_side(settings):
        s = settings  # an occupancy's grids lie one after the other along z
        return max(DIRECTIONS, VOXELS_PER_CELL * s.grid_levels * s.grid_phases) * s.lpv_resolution

    def _level_layers(self):  # its occupancy holds every phase: a level's first
        return range(0, len(self.grids), len(self.grids) // len(self.levels))

    def _layers(self):
        return self.volumes[0].occupancy.march_layers(self._level_layers())

    def _build(self, maps, mesh, scene_bounds, settings, stats, pattern, sources, receivers, rooms, flux_bound):
        emitters, flux_bound = self._gathered_emitters(maps, mesh, settings, stats, pattern, sources, receivers,
                                                       flux_bound)
        volume = self.volumes[0]
        with self.glc.timed(stats, "inject_ms"):
            self._rooms_apart = volume.mark_cells(rooms)
            volume.cluster(emitters, flux_bound, cluster_levels(self.levels, scene_bounds),
                           1 + rooms.count if self._rooms_apart else 1)
        with self.glc.timed(stats, "gather_ms"):
            volume.gather(settings.singularity_bound, self._level_layers(), self._rooms_apart)

    def cell_rooms(self):
        return self.volumes[0].receiving if self._rooms_apart else None

    def cell_light(self):
        """A light grid's mean irradiance over its six directions."""
        return self.volumes[0].read_irradiance(0).mean(axis=0).transpose(2, 1, 0, 3)


class VPLGatherMethod(GatheringMethod):
    """Every pixel gathers the VPLs' light after the G-buffer (gpu/vpl_gather.py); the
    build only voxelises (inject_ms) and bounces."""

    name = "vpl_gather"
    stages = ("inject_ms",)
    gathers_per_pixel = True

    def __init__(self, glc, grids, phases):
        self.emitter_sets = []  # what every pixel gathers from: (buffer, count) pairs
        super().__init__(glc, grids, phases)

    def _volumes(self):
        return [VPLGather(self.glc, self.levels)]

    @classmethod
    def needed_bytes(cls, settings, scene, pixels, mapped):
        return pixel_gather_bytes(settings, scene, pixels) + cls.bounce_bytes(settings, scene)

    @staticmethod
    def longest_side(settings):
        return GATHER_VOXELS_PER_CELL * settings.grid_levels * settings.lpv_resolution

    def _layers(self):
        return self.volumes[0].occupancy.every_grid_layers()

    def _build(self, maps, mesh, scene_bounds, settings, stats, pattern, sources, receivers, rooms, flux_bound):
        self.emitter_sets, _ = self._gathered_emitters(maps, mesh, settings, stats, pattern, sources, receivers,
                                                       flux_bound)

    def gather_pixels(self, targets, uniforms, camera_position, singularity_bound, pattern, held_bound,
                      room_sides=None):
        self.volumes[0].gather(targets, uniforms, camera_position, self.emitter_sets, singularity_bound, pattern,
                               held_bound, room_sides)

    def pixel_gather(self):
        return self.volumes[0]  # its own occupancy and images: its gather comes later in the frame


INDIRECT_METHOD_CLASSES = {method.name: method for method in (LPVMethod, LightGridMethod, VPLGatherMethod)}
"""Each indirect method's class by its name: the one place a name chooses a method."""
assert tuple(INDIRECT_METHOD_CLASSES) == INDIRECT_METHODS

INDIRECT_STAGES = {name: method.stages for name, method in INDIRECT_METHOD_CLASSES.items()}
"""The timed stages of each method (stats keys), by its name."""


def indirect_method(settings):
    """The class of the settings' indirect method."""
    return INDIRECT_METHOD_CLASSES[settings.indirect_method]
