"""Runs the stages G-buffer -> grid placement -> RSM -> VPL -> indirect grids (LPV or
light grid) -> shade, caching each by what it depends on.

A stage is redone only when its inputs change (docs/architecture.md, "A viewport update:
what each edit redoes"): a camera move reuses every light's RSM and VPLs and the indirect
grids while the grids it asks for still fit (gpu/grids.py keep_or_move), and a sun's map
while the region the grids cover stays; a light change redoes that light's RSM and VPLs
and the grids; a geometry change redoes everything.
"""
import time
from dataclasses import dataclass

import numpy as np

from .capacity import check_frame_fits
from .context import GLContext, resource_bytes
from .debug_views import render_debug_passes
from .emitter_bounce import Receivers
from .emitter_grid import EmitterGrid, grid_resolution
from .emitter_shadows import EmitterShadows
from .errors import LPVError
from .frame_lights import frame_lights, seen_box
from .grids import fit_grid, keep_or_move, level_boxes
from .indirect import IndirectGrids
from .mesh_buffer import MeshBuffer
from .passes import DEBUG_PASS_NAMES, PASS_NAMES
from .rsm import PROJECTION_PARABOLOID, cube_face_count, render_rsm
from .settings import DisplaySettings, Settings
from .shade import (FrameTargets, bind_gbuffer, gbuffer_uniforms, read_gbuffer_record, render_gbuffer, render_glow,
                    seen_points, shade_direct, shade_indirect)
from .surface_emitters import SurfaceEmission
from .vpl import VPLSampler
from .warp import STATUS_NAMES, warp_paraboloid_map


# `auto` tessellates a light's paraboloids when this share of the texels that found
# geometry is still failed or only approximate after WDPM (docs/method.md, "auto").
AUTO_TESSELLATION_SHARE = 0.10


AUTO_METHODS = ("cm", "wdpm", "twdpm")  # what `auto` may choose for a light

STAGES = {"rsm_ms": "RSM", "warp_ms": "warp", "vpl_ms": "VPLs", "gbuffer_ms": "G-buffer", "place_ms": "place grids",
          "emitter_upload_ms": "emitter upload", "emitter_grid_ms": "emitter grid",
          "emitter_shadow_ms": "emitter shadows", "inject_ms": "inject", "bounce_ms": "bounces",
          "emitter_bounce_ms": "emitter bounce", "propagate_ms": "propagate", "gather_ms": "gather",
          "direct_ms": "direct", "emitter_light_ms": "emitter light", "emission_ms": "emission",
          "pixel_gather_ms": "pixel gather", "indirect_ms": "indirect"}
"""A frame's timed stages (its stats keys) in the order they run, with their names: the
indirect stage's inject and propagate (LPV), inject, bounces and gather (light grid) or
inject and bounces (VPL gathering, whose pixel gather follows the G-buffer)."""


def render_once(scene, settings, glc=None, **render_args):
    """One frame of `scene`, converged as `settings` ask, by a pipeline built for it and
    released after."""
    pipeline = Pipeline(settings, glc)
    try:
        return pipeline.render_converged(scene, **render_args)
    finally:
        pipeline.release()


@dataclass(frozen=True)
class MapRecipe:
    """How a method makes a light's map: the projection rendered ("cm" or "dpm"), the
    TDPM tessellation unit (None: not tessellated) and the warp's alpha (None: no warp)."""

    projection: str
    tessellation_unit: float = None
    warp_alpha: float = None


def map_recipe(settings, method):
    return MapRecipe("cm" if method == "cm" else "dpm",
                     settings.tessellation_unit if method in ("tdpm", "twdpm") else None,
                     {"wdpm": settings.warp_alpha, "twdpm": settings.tessellated_warp_alpha}.get(method))


def auto_method(light):
    """`auto`'s first choice for a light: the cube's front face alone for a spot of
    half-angle <= 45 degrees (one exact render), WDPM otherwise (a sun's map is
    orthographic whatever the method)."""
    if light.kind == "SUN" or cube_face_count(light) == 1:
        return "cm"
    return "wdpm"


FAR_FIELD_SHARE = 0.25
"""A sun with a map of its own region gets this share of its VPL count again from its
whole map outside that region: the far ground a house's walls see to the horizon."""


@dataclass
class LightMaps:
    """One light's RSM (warped for WDPM), its VPLs, the method that made them, for the
    warped methods the warp status, and for a sun whose map spans far more than the camera
    sees, the map of the region it sees (`region`, the box `region_box`) that the VPLs come
    from, with `far_vpls` from the whole map outside it; and the Poisson pattern of the
    VPLs (gpu/vpl.py)."""

    rsm: object
    method: str
    warp: object = None
    region: object = None
    region_box: tuple = None
    vpls: object = None
    far_vpls: object = None
    pattern: int = None

    @property
    def vpl_map(self):
        """The map the VPLs were sampled from."""
        return self.region if self.region is not None else self.rsm

    def sample_vpls(self, sampler, count, pattern):
        """(Re)sample the VPLs (and a sun's far field) in Poisson pattern `pattern`."""
        for vpls in (self.vpls, self.far_vpls):
            if vpls is not None:
                vpls.release()
        self.vpls = sampler.sample(self.vpl_map, count, pattern)
        self.far_vpls = None if self.region is None else sampler.sample(
            self.rsm, max(1, int(count * FAR_FIELD_SHARE)), pattern, exclude=self.region_box)
        self.pattern = pattern

    def emitter_sets(self):
        """The light's VPL buffers with their counts, for the indirect stage."""
        return [(vpls.buffer, vpls.count) for vpls in (self.vpls, self.far_vpls) if vpls is not None]

    @property
    def vpl_count(self):
        return sum(count for _, count in self.emitter_sets())

    def resources(self):
        """The GPU memory of the maps, VPLs and warp status."""
        held = (self.rsm.position, self.rsm.normal, self.rsm.flux, *(buffer for buffer, _ in self.emitter_sets()))
        held += (self.warp.texture,) if self.warp is not None else ()
        held += (self.region.position, self.region.normal, self.region.flux) if self.region is not None else ()
        return held

    def release(self):
        for resource in (self.rsm, self.vpls, self.far_vpls, self.warp, self.region):
            if resource is not None:
                resource.release()


SUN_REGION_SHARE = 0.5
"""A sun's VPLs come from a map of the region the grids cover when that region is less
than this share of the scene's size: over a 200 m ground, a map of the whole ground
leaves a house the camera looks at a handful of VPLs."""


def sun_region(levels, bounds):
    """The box of the coarsest grid level within the scene's bounds, as a hashable pair
    of tuples, when it is small enough to need a map of its own (SUN_REGION_SHARE); None
    otherwise."""
    if not levels:
        return None
    low, high = seen_box(levels, bounds)
    if np.any(high <= low) or np.max(high - low) >= SUN_REGION_SHARE * np.max(bounds[1] - bounds[0]):
        return None
    return tuple(map(float, low)), tuple(map(float, high))


@dataclass
class Frame:
    """The passes (name -> (height, width, 3) float32 linear, top row first), statistics,
    and the combined image as a viewport draws it ((height, width, 4), bottom row first,
    in the caller's buffer; None unless asked for)."""

    passes: dict
    stats: dict
    display: object = None


class Pipeline:
    """The cached results of every stage, in the process's shared GL context."""

    def __init__(self, settings=None, glc=None):
        self.settings = settings or Settings()
        self.glc = glc or GLContext.shared()
        self.vpl_sampler = VPLSampler(self.glc)
        self._mesh = None          # (geometry key, MeshBuffer)
        self._lights = {}          # light cache key -> LightMaps
        self._indirect = None      # (key, IndirectGrids)
        self._emission = None      # SurfaceEmission of the emissive surfaces, over the last frame's levels
        self._emitter_grid = None  # EmitterGrid of the point emitters
        self._emitter_shadows = None  # EmitterShadows of the point emitters, over the last frame's grids
        self._frame_lights = None  # (what it depends on, the last frame's FrameLights)
        self._receivers = None     # (geometry key, Receivers of the emitters' bounce)
        self._targets = None
        self._shown_keys = ()      # the light cache keys of the last frame
        self._fits = None          # what the last frame that fitted the machine depended on
        self._placement = None     # (what it depends on, the grids placed around the view)
        self.last_origin = np.zeros(3)  # the world point the last frame's positions are relative to
        self.vpl_pattern = 0       # the Poisson pattern of the VPLs (gpu/vpl.py)
        self._accumulated = None   # (the last frame's view, scene and settings, VPL sets in it, VPLs in it)

    @property
    def last_light_maps(self):
        """The LightMaps the last frame was made of (none once invalidated), for the overlays."""
        return [self._lights[key] for key in self._shown_keys if key in self._lights]

    @property
    def last_indirect(self):
        """The last frame's IndirectGrids (gpu/indirect.py), for the overlays."""
        return self._indirect[1] if self._indirect is not None else None

    @property
    def last_indirect_key(self):
        """What the indirect grids' content depends on: the method, every light's key, the
        grids and the steps."""
        return self._indirect[0] if self._indirect is not None else None

    @property
    def last_emitter_grid(self):
        """The EmitterGrid of the last frame's point emitters (gpu/emitter_grid.py), or None."""
        return self._emitter_grid

    @property
    def targets(self):
        """The camera's G-buffer and images of the last frame (gpu/shade.py FrameTargets)."""
        return self._targets

    def light_maps(self, scene, stats=None, levels=None, lights=None):
        """Each light's LightMaps (of `lights`, by default the scene's), rendered only when
        the light, geometry, settings or (for a sun) the region of the grid `levels`
        changed, its VPLs sampled again when the pattern (`vpl_pattern`) changed; and their
        cache keys."""
        stats = {} if stats is None else stats
        s = self.settings
        geometry_key = self._upload(scene, stats)
        bounds = scene.bounds()
        maps, keys = [], []
        recipes = tuple(map_recipe(s, m) for m in (AUTO_METHODS if s.method == "auto" else (s.method,)))
        if any(recipe.warp_alpha is not None for recipe in recipes):
            recipes += (s.warp_iterations, s.warp_significant_figures)
        region = sun_region(levels, bounds)
        for light in scene.lights if lights is None else lights:
            light_region = region if light.kind == "SUN" else None
            key = (light.key(), geometry_key, s.method, s.rsm_resolution, s.vpls_per_light, recipes, light_region)
            if key not in self._lights:
                self._lights[key] = self._render_light(light, bounds, stats, light_region)
            light_maps = self._lights[key]
            if light_maps.pattern != self.vpl_pattern:
                with self.glc.timed(stats, "vpl_ms"):
                    light_maps.sample_vpls(self.vpl_sampler, s.vpls_per_light, self.vpl_pattern)
            maps.append(light_maps)
            keys.append(key)
        for stale in set(self._lights) - set(keys):
            self._lights.pop(stale).release()
        return maps, keys

    def _render_light(self, light, bounds, stats, region=None):
        if self.settings.method != "auto":
            return self._render_light_with(self.settings.method, light, bounds, stats, region)
        maps = self._render_light_with(auto_method(light), light, bounds, stats, region)
        if maps.warp is not None:
            found = sum(maps.warp.counts[name] for name in STATUS_NAMES[1:])
            unresolved = maps.warp.counts["failed"] + maps.warp.counts["approximate"]
            if unresolved > AUTO_TESSELLATION_SHARE * found:
                maps.release()
                maps = self._render_light_with("twdpm", light, bounds, stats, region)
        return maps

    def _render_light_with(self, method, light, bounds, stats, region=None):
        s = self.settings
        recipe = map_recipe(s, method)
        with self.glc.timed(stats, "rsm_ms"):
            rsm = render_rsm(self.glc, self._mesh[1], light, s.rsm_resolution, bounds, recipe.projection,
                             recipe.tessellation_unit)
        status = None
        if recipe.warp_alpha is not None and rsm.projection_kind == PROJECTION_PARABOLOID:
            with self.glc.timed(stats, "warp_ms"):
                warped, status = warp_paraboloid_map(self.glc, rsm, recipe.warp_alpha, s.warp_iterations,
                                                     s.warp_significant_figures)
            rsm.release()
            rsm = warped
        region_map = None
        if region is not None:
            with self.glc.timed(stats, "rsm_ms"):
                region_map = render_rsm(self.glc, self._mesh[1], light, s.rsm_resolution,
                                        tuple(np.array(corner) for corner in region), reach=bounds)
        maps = LightMaps(rsm, method, status, region_map, region)
        with self.glc.timed(stats, "vpl_ms"):
            maps.sample_vpls(self.vpl_sampler, s.vpls_per_light, self.vpl_pattern)
        return maps

    def render(self, scene, settings=None, passes=PASS_NAMES, display_into=None, display_settings=None,
               vpl_set=None, accumulate=False, read=True):
        """Render the scene from its camera; returns a Frame with the `passes` asked for
        (read back from the GPU; PASS_NAMES and the debug passes DEBUG_PASS_NAMES, whose
        splat size `display_settings` gives), and with `display_into` (a writable buffer
        of width x height x 4 float32) the combined image read into it as RGBA rows,
        bottom row first: what a viewport draws, read with no copy on the way. A frame
        the driver's limits or the memory free cannot hold is refused before anything of
        it is allocated (capacity.py).

        `vpl_set` picks the VPLs' Poisson pattern (None: the one the last frame used). With
        `read` false the passes are made but not read back (the Frame has none): a caller
        that averages more sets reads them once, at the end.
        With `accumulate`, a frame of the same view, scene and settings as the last one
        averages its indirect light with the last one's, VPL set by VPL set (stats
        `vpl_sets`, `accumulated_vpls`); anything else starts the average again."""
        if settings is not None:
            self.settings = settings
        s = self.settings
        if scene.camera is None:
            raise LPVError("The scene has no camera; add a camera and make it the scene's active camera.")
        if not scene.sanitized:
            scene.sanitize()
        fits = (s, scene.geometry_key(), tuple(light.key() for light in scene.lights), scene.point_emitters_key(),
                tuple(passes), display_into is not None)
        if fits != self._fits:  # a viewport redraw of the same frame size and scene asks nothing again
            check_frame_fits(self.glc, s, scene, passes, display_into is not None, held_bytes=self.gpu_bytes())
            self._fits = fits
        view = (scene.camera.key(), *fits[:4])
        adding = accumulate and self._accumulated is not None and self._accumulated[0] == view
        start = time.perf_counter()
        stats = {}
        self._upload(scene, stats)
        if self._targets is None or self._targets.size != (s.width, s.height):
            if self._targets is not None:
                self._targets.release()
                self._targets = None  # until the new ones are made, which a driver may refuse
            self._targets = FrameTargets(self.glc.gl, s.width, s.height)
        targets = self._targets
        if not adding:  # another VPL set of the same view finds its G-buffer and direct light made
            with self.glc.timed(stats, "gbuffer_ms"):
                render_gbuffer(self.glc, self._mesh[1], scene.camera, targets)
        placement_key = (scene.camera.key(), self._mesh[0], s.lpv_resolution, s.grid_levels, s.grid_phases,
                         s.grid_shift, s.width, s.height)
        if self._placement is None or self._placement[0] != placement_key:
            with self.glc.timed(stats, "place_ms"):  # the G-buffer read back: only when the view changed
                boxes = level_boxes(seen_points(self.glc, targets, scene.camera), scene.bounds(), s.grid_levels)
                self._placement = (placement_key, tuple(
                    fit_grid(box, s.lpv_resolution, s.grid_shift + phase / s.grid_phases)
                    for box in boxes for phase in range(s.grid_phases)))
        placed = self._placement[1]
        previous = self._indirect[1].grids if self._indirect is not None else None
        grids = keep_or_move(previous, placed)
        levels = list(grids[::s.grid_phases])
        if vpl_set is not None:
            self.vpl_pattern = vpl_set
        box = seen_box(levels, scene.bounds())
        lit_key = (fits[3], fits[2], tuple(map(tuple, box)), levels[0].cell_size, s.light_cutoff, s.light_map_budget)
        if self._frame_lights is None or self._frame_lights[0] != lit_key:
            self._frame_lights = (lit_key, frame_lights(scene, s, box, levels[0].cell_size))
        lit = self._frame_lights[1]
        maps, keys = self.light_maps(scene, stats, levels, lit.mapped)
        sources, sources_key = self._emitter_sources(scene, s, lit, box, grids, stats)
        vpl_count = int(sum(m.vpl_count for m in maps))
        if adding:
            sets, accumulated_vpls = self._accumulated[1] + 1, self._accumulated[2] + vpl_count
        else:
            sets, accumulated_vpls = 1, vpl_count
        self._accumulated = None  # until this set is in the image
        indirect_key = (s.indirect_method, tuple(keys), self.vpl_pattern, grids, s.propagation_iterations,
                        s.occlusion, sources_key)
        indirect_key += (s.singularity_bound, s.bounces) if s.indirect_method != "lpv" else ()
        if self._indirect is None or self._indirect[0] != indirect_key:
            indirect = self._indirect[1] if self._indirect is not None else None
            if indirect is not None and (indirect.method, indirect.grids) != (s.indirect_method, grids):
                indirect.release()
                indirect = None
            if indirect is None:
                indirect = IndirectGrids(self.glc, s.indirect_method, grids, s.grid_phases)
            indirect.build(maps, self._mesh[1], scene.bounds(), s, stats, self.vpl_pattern, sources,
                           lambda: self._receivers_of(scene).rows(s.emitter_bounce_samples, self.vpl_pattern))
            self._indirect = (indirect_key, indirect)
        indirect = self._indirect[1]
        drawn = len(lit.emitters) - lit.lights_as_emitters  # the scene's point emitters, not the lamps
        glowing = scene.emission is not None or drawn > 0
        if not adding:
            with self.glc.timed(stats, "direct_ms"):
                for m in maps:
                    shade_direct(self.glc, targets, scene.camera, m.rsm, s.shadow_bias)
            if len(lit.emitters):
                with self.glc.timed(stats, "emitter_light_ms"):
                    self._emitter_grid.add_light(targets, gbuffer_uniforms(scene.camera), s,
                                                 self._emitter_shadows if s.emitter_shadows else None)
            if glowing:
                with self.glc.timed(stats, "emission_ms"):
                    if scene.emission is not None:
                        self._emitted_light(scene, s, targets, levels, indirect)
                    render_glow(self.glc, self._mesh[1], scene.camera, targets,
                                (self._emitter_grid.emitters, drawn) if drawn else None)
        if s.indirect_method == "vpl_gather":
            with self.glc.timed(stats, "pixel_gather_ms"):
                bind_gbuffer(targets)
                # the n-th set of a converging frame bounds 1/r² by 1/n as much: the average's bias tends to zero
                indirect.volumes[0].gather(targets, gbuffer_uniforms(scene.camera), scene.camera.position,
                                           indirect.emitter_sets, s.singularity_bound / sets, self.vpl_pattern)
        with self.glc.timed(stats, "indirect_ms"):
            shade_indirect(self.glc, targets, scene.camera, indirect, len(levels), s.grid_phases, s.indirect_intensity,
                           display_into is not None, sets - 1, glow=glowing)
        self._accumulated = (view, sets, accumulated_vpls)
        self._shown_keys = tuple(keys)
        self.last_origin = scene.world_origin
        if read and any(name in DEBUG_PASS_NAMES for name in passes):
            with self.glc.timed(stats, "debug_ms"):
                self.draw_debug_passes(scene, display_settings)
        with self.glc.timed(stats, "readback_ms"):
            images = {name: targets.read(name) for name in passes} if read else {}
            display = None if display_into is None else targets.read_display_into(display_into)
        stats["total_ms"] = (time.perf_counter() - start) * 1000.0
        warped = [m.warp for m in maps if m.warp is not None]
        if warped:
            stats["warp_status"] = {name: sum(w.counts[name] for w in warped) for name in STATUS_NAMES}
        stats.update({
            "method": s.method,
            "light_methods": [m.method for m in maps],
            "vpl_count": vpl_count,
            "vpl_pattern": self.vpl_pattern,
            "vpl_sets": sets,
            "accumulated_vpls": accumulated_vpls,
            "lights": len(scene.lights),
            "mapped_lights": len(lit.mapped),
            "lights_as_emitters": lit.lights_as_emitters,
            "skipped_lights": lit.skipped_lights,
            "point_emitters": len(lit.emitters),
            "skipped_emitters": lit.skipped_emitters,
            "triangles": scene.triangle_count,
            "dropped_triangles": dict(scene.dropped),
            "images": [image.name for image in scene.images],
            "approximated_materials": list(scene.approximated_materials),
            "rsm_resolution": s.rsm_resolution,
            "rsm_faces": int(sum(m.rsm.face_count for m in maps)),
            "indirect_method": s.indirect_method,
            "lpv_resolution": s.lpv_resolution,
            "lpv_cell_size": grids[0].cell_size,
            "grid_levels": len(levels),
            "propagation_iterations": s.propagation_iterations,
            "image_size": [s.width, s.height],
            "renderer": self.glc.renderer,
        })
        return Frame(images, stats, display)

    def render_converged(self, scene, settings=None, passes=PASS_NAMES, display_settings=None, stop=None,
                         progress=None):
        """A frame whose indirect light averages VPL sets of patterns 0, 1, 2, ...: as many
        as the settings' `converge_sets`, or while `converge_seconds` last when above zero
        (the first set is always made), or until `stop()` is true; `progress(sets done)`
        after each. Stats: `converge_ms` the time of them all, each stage's ms their sum."""
        s = settings or self.settings
        start = time.perf_counter()
        single = s.converge_seconds <= 0 and s.converge_sets <= 1  # else the passes are read once, at the end
        frame = self.render(scene, s, passes=passes, display_settings=display_settings, vpl_set=0, read=single)
        spent = {key: value for key, value in frame.stats.items() if key.endswith("_ms")}
        if s.converge_seconds > 0:
            done = lambda: time.perf_counter() - start >= s.converge_seconds  # noqa: E731
        else:
            done = lambda: frame.stats["vpl_sets"] >= s.converge_sets  # noqa: E731
        while not done() and not (stop is not None and stop()):
            if progress is not None:
                progress(frame.stats["vpl_sets"])
            frame = self.render(scene, s, passes=(), vpl_set=frame.stats["vpl_sets"], accumulate=True)
            for key, value in frame.stats.items():
                if key.endswith("_ms") and key != "total_ms":
                    spent[key] = spent.get(key, 0.0) + value
        if not single:
            if any(name in DEBUG_PASS_NAMES for name in passes):
                with self.glc.timed(spent, "debug_ms"):
                    self.draw_debug_passes(scene, display_settings)
            with self.glc.timed(spent, "readback_ms"):
                frame.passes = {name: self._targets.read(name) for name in passes}
            frame.stats.update({key: value for key, value in spent.items() if key != "total_ms"})
        frame.stats["converge_ms"] = (time.perf_counter() - start) * 1000.0
        return frame

    def read_gbuffer(self, scene):
        """The last frame's G-buffer as a GBufferRecord (gpu/shade.py), for the corrections."""
        return read_gbuffer_record(self.glc, self._targets, scene.camera)

    def draw_debug_passes(self, scene, display_settings=None):
        """Draw the last frame's debug passes (DEBUG_PASS_NAMES) into its images."""
        render_debug_passes(self.glc, self._targets, scene.camera, self.last_light_maps,
                            (display_settings or DisplaySettings()).vpl_point_size)

    def _emitter_sources(self, scene, s, lit, box, grids, stats):
        """Build the emitter grid of the frame's point emitters (when it has any) and their
        shadows' light grid over `grids`, and sample the emissive surfaces' emitters; the
        (buffer, count) sets whose light bounces, and a key of what they hold."""
        sources, key = [], ()
        if not len(lit.emitters) or not s.emitter_shadows:
            if self._emitter_shadows is not None:
                self._emitter_shadows.release()
                self._emitter_shadows = None
        if not len(lit.emitters) and self._emitter_grid is not None:
            self._emitter_grid.release()
            self._emitter_grid = None
        if len(lit.emitters):
            resolution = grid_resolution(s.emitter_grid_resolution)
            if self._emitter_grid is None or self._emitter_grid.resolution != resolution:
                if self._emitter_grid is not None:
                    self._emitter_grid.release()
                self._emitter_grid = EmitterGrid(self.glc, s.emitter_grid_resolution)
            with self.glc.timed(stats, "emitter_upload_ms"):
                self._emitter_grid.upload(lit.emitters, lit.key)
            if s.emitter_light == "grid":
                with self.glc.timed(stats, "emitter_grid_ms"):
                    self._emitter_grid.build(box, s.singularity_bound)
            if s.emitter_shadows:
                if self._emitter_shadows is None or self._emitter_shadows.grids != grids:
                    if self._emitter_shadows is not None:
                        self._emitter_shadows.release()
                    self._emitter_shadows = EmitterShadows(self.glc, grids, s.grid_phases)
                with self.glc.timed(stats, "emitter_shadow_ms"):
                    self._emitter_shadows.build(
                        self._mesh[1], [(self._emitter_grid.emitters, self._emitter_grid.count)], lit.flux_bound,
                        lit.bounds(scene.bounds()), s.singularity_bound, (lit.key, self._mesh[0], s.singularity_bound))
            sources.append((self._emitter_grid.emitters, self._emitter_grid.count))
            key += lit.key
        if scene.emission is not None:
            if self._emission is None:
                self._emission = SurfaceEmission(self.glc)
            self._emission.sample(scene, s.emission_samples, self.vpl_pattern)
            sources.append((self._emission.emitters, self._emission.count))
            key += (scene.geometry_key(), s.emission_samples)
        # what the bounce marches through and bounds, whichever method gathers it
        return sources, key + ((self._mesh[0], s.emitter_bounce_samples, s.singularity_bound) if sources else ())

    def _receivers_of(self, scene):
        """The emitters' bounce's Receivers of the scene's geometry, made once a geometry."""
        if self._receivers is None or self._receivers[0] != scene.geometry_key():
            self._receivers = (scene.geometry_key(), Receivers(scene))
        return self._receivers[1]

    def _emitted_light(self, scene, s, targets, levels, indirect):
        """Add the direct light of the scene's emissive surfaces into the direct image,
        gathered through VPL gathering's own occupancy and images when that is the
        indirect method (its gather comes later in the frame)."""
        gather = indirect.volumes[0] if indirect.method == "vpl_gather" else self._emission.own_gather(levels)
        bind_gbuffer(targets)
        self._emission.add_light(gather, self._mesh[1], targets, gbuffer_uniforms(scene.camera),
                                 scene.camera.position, s.singularity_bound, self.vpl_pattern)

    def gpu_bytes(self):
        """GPU memory the pipeline holds now: mesh, light maps, VPLs, LPV, camera images."""
        held = [*self.vpl_sampler.resources()]
        held += self._mesh[1].resources() if self._mesh is not None else ()
        held += self._indirect[1].resources() if self._indirect is not None else ()
        held += self._emission.resources() if self._emission is not None else ()
        held += self._emitter_grid.resources() if self._emitter_grid is not None else ()
        held += self._emitter_shadows.resources() if self._emitter_shadows is not None else ()
        for maps in self._lights.values():
            held += maps.resources()
        held += self._targets.resources() if self._targets is not None else ()
        return resource_bytes(*held)

    def invalidate(self):
        """Forget every cached stage result, so the next render redoes every stage."""
        for maps in self._lights.values():
            maps.release()
        self._lights.clear()
        self._placement = None
        self._accumulated = None
        self._frame_lights = None
        self._receivers = None
        for cached in ("_emission", "_emitter_grid", "_emitter_shadows"):
            if getattr(self, cached) is not None:
                getattr(self, cached).release()
                setattr(self, cached, None)
        if self._indirect is not None:
            self._indirect[1].forget()
            self._indirect = (None, self._indirect[1])  # keep the volumes' memory, forget their content

    def _upload(self, scene, stats):
        key = scene.geometry_key()
        if self._mesh is None or self._mesh[0] != key:
            if self._mesh is not None:
                self._mesh[1].release()
            with self.glc.timed(stats, "upload_ms"):
                self._mesh = (key, MeshBuffer(self.glc, scene))
        return key

    def release(self):
        self.invalidate()
        if self._indirect is not None:
            self._indirect[1].release()
        self._indirect = None
        if self._mesh is not None:
            self._mesh[1].release()
        if self._targets is not None:
            self._targets.release()
        self.vpl_sampler.release()
