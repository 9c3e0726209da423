"""Runs a frame's steps, caching each by what it depends on: G-buffer -> grid placement ->
light maps (RSM, VPLs) -> emitter sources -> indirect light (the method's build, gpu/
indirect.py) -> direct light -> composite (the method's pixel gather, the lookup) -> read.

A stage is redone only when its inputs change (docs/architecture.md, "A viewport update:
what each edit redoes"): a camera move reuses every light's RSM and VPLs and the indirect
grids while the grids it asks for still fit (gpu/grids.py keep_or_move), and a sun's map
while the region the grids cover stays; a light change redoes that light's RSM and VPLs
and the grids; a geometry change redoes everything.
"""
import time
from dataclasses import dataclass, replace

import numpy as np

from .bounces import light_bounces
from .capacity import check_frame_fits
from .closed_meshes import ClosedMeshes
from .context import GLContext, resource_bytes
from .debug_views import render_debug_passes
from .emitter_bounce import EmitterSources, Receivers
from .emitter_grid import EmitterGrid, grid_resolution
from .emitter_shadows import EmitterShadows
from .errors import LPVError
from .frame_lights import frame_lights, seen_box
from .grids import fit_grid, keep_or_move, level_boxes
from .indirect import indirect_method
from .keyed_cache import KeyedCache
from .light_maps import AUTO_METHODS, cascade_boxes, map_recipe, render_light_maps, sun_region
from .mesh_buffer import MeshBuffer
from .passes import DEBUG_PASS_NAMES, PASS_NAMES
from .pixel_filter import pixel_offset
from .scene import array_key
from .settings import DisplaySettings, Settings
from .shade import (FrameTargets, ReflectionInputs, bind_gbuffer, gbuffer_uniforms, read_gbuffer_record, render_gbuffer,
                    render_glow, seen_points, shade_direct, shade_indirect)
from .soft_shadows import shadow_uniforms
from .surface_emitters import SurfaceEmission
from .vpl import VPLSampler, glossy_blur_alpha
from .warp import STATUS_NAMES
from .world_light import WorldLight, world_lights


STAGES = {"rsm_ms": "RSM", "warp_ms": "warp", "vpl_ms": "VPLs", "gbuffer_ms": "G-buffer", "place_ms": "place grids",
          "emitter_upload_ms": "emitter upload", "emitter_grid_ms": "emitter grid",
          "emitter_shadow_ms": "emitter shadows", "inject_ms": "inject", "bounce_ms": "bounces",
          "emitter_bounce_ms": "emitter bounce", "propagate_ms": "propagate", "gather_ms": "gather",
          "direct_ms": "direct", "emitter_light_ms": "emitter light", "emission_ms": "emission",
          "world_ms": "world", "pixel_gather_ms": "pixel gather", "indirect_ms": "indirect"}
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


@dataclass
class Frame:
    """The passes (name -> (height, width, 3) float32 linear, top row first), statistics,
    the combined image as a viewport draws it ((height, width, 3), bottom row first, in
    the caller's buffer; None unless asked for), and with the combined pass its coverage
    ((height, width): 1 where the camera sees a surface or an emitter, 0 where it sees the
    background; Film Transparent's alpha)."""

    passes: dict
    stats: dict
    display: object = None
    coverage: object = None


class Pipeline:
    """The cached results of every stage, in the process's shared GL context."""

    def __init__(self, settings=None, glc=None):
        self.settings = settings or Settings()
        self.glc = glc or GLContext.shared()
        self.vpl_sampler = VPLSampler(self.glc)
        self._mesh = KeyedCache(releases=True)       # geometry key -> MeshBuffer
        self._lights = {}                             # light cache key -> LightMaps
        self._indirect = KeyedCache(releases=True)   # what the content depends on -> IndirectMethod
        self._emission = None      # SurfaceEmission of the emissive surfaces
        self._world = None         # WorldLight: the world's emitters and background map
        self._emitter_grid = KeyedCache(releases=True)     # resolution -> EmitterGrid of the point emitters
        self._emitter_shadows = KeyedCache(releases=True)  # grids -> EmitterShadows of the point emitters
        self._frame_lights = KeyedCache()  # what it depends on -> the last frame's FrameLights
        self._receivers = KeyedCache(releases=True)  # geometry key -> Receivers of the bounces' points
        self._closed_meshes = KeyedCache()  # enclosure key -> ClosedMeshes
        self._open_sides = KeyedCache()    # enclosure and emitters' keys -> the sides of faces light reaches, rooms
        self._targets = KeyedCache(releases=True)    # image size -> FrameTargets
        self._placement = KeyedCache()     # what it depends on -> the grids placed around the view, the sun cascades
        self._cascade_boxes = ()   # the boxes of a sun's direct-light cascade (gpu/light_maps.py cascade_boxes)
        self._shown_keys = ()      # the light cache keys of the last frame
        self._gbuffer_offset = False  # the last G-buffer looks through a point off the pixels' centres
        self._gbuffer_drawn = None  # what the G-buffer in the targets was drawn of (_gbuffer)
        self._fits = None          # what the last frame that fitted the machine depended on
        self.last_origin = np.zeros(3)  # the world point the last frame's positions are relative to
        self.vpl_pattern = 0       # the Poisson pattern of the VPLs (gpu/vpl.py)
        self._accumulated = None   # (the last frame's view, scene and settings, VPL sets in it, VPLs in it)

    @property
    def last_light_maps(self):
        """The LightMaps the last frame was made of (none once invalidated), for the overlays."""
        return [self._lights[key] for key in self._shown_keys if key in self._lights]

    @property
    def last_indirect(self):
        """The last frame's indirect method (gpu/indirect.py IndirectMethod), for the overlays."""
        return self._indirect.value

    @property
    def last_indirect_key(self):
        """What the indirect grids' content depends on: the method, every light's key, the
        grids and the steps."""
        return self._indirect.key

    @property
    def last_emitter_grid(self):
        """The EmitterGrid of the last frame's point emitters (gpu/emitter_grid.py), or None."""
        return self._emitter_grid.value

    @property
    def targets(self):
        """The camera's G-buffer and images of the last frame (gpu/shade.py FrameTargets)."""
        return self._targets.value

    def light_maps(self, scene, stats=None, levels=None, lights=None):
        """Each light's LightMaps (of `lights`, by default the scene's), rendered only when
        the light, its room (gpu/closed_meshes.py), the geometry, settings or (for a sun)
        the region of the grid `levels` changed, its VPLs sampled again when the pattern (`vpl_pattern`) changed; and their
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
        self._sides(scene)
        rooms = self._rooms()
        for light in scene.lights if lights is None else lights:
            light_region = region if light.kind == "SUN" else None
            room = rooms.room_of(light) if rooms is not None else 0
            key = (light.key(), geometry_key, s.method, s.rsm_resolution, s.vpls_per_light, recipes, light_region,
                   self.vpl_pattern if self._mesh.value.hashed else None, room,  # hashed cut-outs differ per pattern
                   scene.filter_glossy)
            if key not in self._lights:
                self._lights[key] = render_light_maps(self.glc, self._mesh.value, light, s, bounds, stats,
                                                      self.vpl_sampler, self.vpl_pattern, light_region, room,
                                                      glossy_blur_alpha(scene.filter_glossy))
            light_maps = self._lights[key]
            if light.kind == "SUN" and levels:
                light_maps.fit_view_maps(self.glc, self._mesh.value, s.sun_cascade_resolution, self._cascade_boxes, bounds,
                                         stats)
            if light_maps.pattern != self.vpl_pattern:
                with self.glc.timed(stats, "vpl_ms"):
                    light_maps.sample_vpls(self.vpl_sampler, s.vpls_per_light, self.vpl_pattern)
            maps.append(light_maps)
            keys.append(key)
        for stale in set(self._lights) - set(keys):
            self._lights.pop(stale).release()
        return maps, keys

    def render(self, scene, settings=None, passes=PASS_NAMES, display_into=None, display_settings=None,
               vpl_set=None, accumulate=False, read=True):
        """Render the scene from its camera; returns a Frame with the `passes` asked for
        (read back from the GPU; PASS_NAMES and the debug passes DEBUG_PASS_NAMES, whose
        splat size `display_settings` gives), and with `display_into` (a writable buffer
        of width x height x DISPLAY_CHANNELS float32) the combined image read into it as RGB rows,
        bottom row first: what a viewport draws, read with no copy on the way. A frame
        the driver's limits or the memory free cannot hold is refused before anything of
        it is allocated (capacity.py).

        `vpl_set` picks the VPLs' Poisson pattern (None: the one the last frame used). With
        `read` false the passes are made but not read back (the Frame has none): a caller
        that averages more sets reads them once, at the end.
        With `accumulate`, a frame of the same view, scene and settings as the last one
        averages its light with the last one's, VPL set by VPL set, each set seen through
        another point of the pixels (gpu/pixel_filter.py: anti-aliasing; stats `vpl_sets`,
        `accumulated_vpls`); anything else starts the average again."""
        if settings is not None:
            self.settings = settings
        s = self.settings
        fits = self._check_fits(scene, passes, display_into is not None)
        view = (scene.camera.key(), *fits[:4])
        adding = accumulate and self._accumulated is not None and self._accumulated[0] == view
        sets = self._accumulated[1] + 1 if adding else 1
        camera = scene.camera.jittered(pixel_offset(sets - 1, scene.film.filter_width), (s.width, s.height))
        shot = scene if camera is scene.camera else replace(scene, camera=camera)  # this set's view of the scene
        self._gbuffer_offset = camera is not scene.camera  # the G-buffer looks through a point off the centres
        start = time.perf_counter()
        stats = {}
        if vpl_set is not None:
            self.vpl_pattern = vpl_set
        targets = self._gbuffer(shot, stats)
        grids = self._place_grids(scene, targets, stats)  # placed from the first set's view
        levels = list(grids[::s.grid_phases])
        box = seen_box(levels, scene.bounds())
        lit = self._frame_lights.get(
            (fits[2], tuple(map(tuple, box)), levels[0].cell_size, s.light_cutoff, s.light_map_budget),
            lambda: frame_lights(scene, s, box, levels[0].cell_size))
        maps, keys = self.light_maps(scene, stats, levels, lit.mapped)
        selection = self._select_emitters(scene, s, lit, box, levels[0].cell_size, stats)
        sources, sources_key = self._emitter_sources(scene, s, selection, box, grids, stats)
        vpl_count = int(sum(m.vpl_count for m in maps))
        accumulated_vpls = self._accumulated[2] + vpl_count if adding else vpl_count
        self._accumulated = None  # until this set is in the image
        indirect = self._indirect_light(scene, maps, keys, grids, sources, sources_key, stats)
        drawn = scene.point_emitter_count  # the scene's point emitters (skipped ones draw nothing), not the lamps
        glowing = scene.emission is not None or drawn > 0
        self._direct_light(shot, targets, maps, selection, indirect, drawn, stats)
        self._composite(shot, targets, indirect, sets, display_into is not None, glowing, stats)
        self._accumulated = (view, sets, accumulated_vpls)
        self._shown_keys = tuple(keys)
        self.last_origin = scene.world_origin
        images, coverage, display = self._read(scene, passes, display_into, display_settings, read, stats)
        self.glc.read_timings()
        stats["total_ms"] = (time.perf_counter() - start) * 1000.0
        stats.update(self._statistics(scene, maps, lit, selection, indirect, vpl_count, sets, accumulated_vpls))
        return Frame(images, stats, display, coverage)

    def _check_fits(self, scene, passes, display):
        """Refuse a frame the machine cannot hold (capacity.py), asked again only when what
        it depends on changed (a viewport redraw of the same size and scene, or of as many
        emitters moved, asks nothing); what it depends on."""
        s = self.settings
        if scene.camera is None:
            raise LPVError("The scene has no camera; add a camera and make it the scene's active camera.")
        if not scene.sanitized:
            scene.sanitize()
        lights = tuple(light.key() for light in scene.lights) + ((scene.world.key(),) if scene.world else ())
        fits = (s, scene.geometry_key(), lights, scene.point_emitters_key(), tuple(passes), display)
        checked = (*fits[:3], scene.point_emitter_count, *fits[4:])  # moved emitters need no more memory
        if checked != self._fits:
            check_frame_fits(self.glc, s, scene, passes, display, held_bytes=self.gpu_bytes())
            self._fits = checked
        return fits

    def _gbuffer(self, scene, stats):
        """The mesh uploaded and the camera's images at the frame's size, with its G-buffer."""
        s = self.settings
        self._upload(scene, stats)
        mesh = self._mesh.value
        sides = self._sides(scene)
        mesh.show_open_sides(sides)
        targets = self._targets.get((s.width, s.height), lambda: FrameTargets(self.glc.gl, s.width, s.height))
        drawn = (scene.camera.key(), self._mesh.key, None if sides is None else array_key(sides), targets,
                 self.vpl_pattern if mesh.hashed else None)
        if drawn == self._gbuffer_drawn:  # a light or emitter edit: the same view of the same surfaces
            self.glc.clear(targets.direct)
            return targets
        with self.glc.timed(stats, "gbuffer_ms"):
            render_gbuffer(self.glc, mesh, scene.camera, targets, self.vpl_pattern)
        self._gbuffer_drawn = drawn
        return targets

    def _place_grids(self, scene, targets, stats):
        """The indirect grids (levels x phases) around what the camera sees: placed again
        only when the view changed (the G-buffer read back), the last frame's kept while
        they still fit (gpu/grids.py keep_or_move)."""
        s = self.settings
        sun = any(light.kind == "SUN" for light in scene.lights)  # only a sun's maps follow the view

        def place():
            with self.glc.timed(stats, "place_ms"):
                points = seen_points(self.glc, targets, scene.camera)
                boxes = level_boxes(points, scene.bounds(), s.grid_levels)
                return tuple(fit_grid(box, s.lpv_resolution, s.grid_shift + phase / s.grid_phases)
                             for box in boxes for phase in range(s.grid_phases)), \
                    cascade_boxes(points, scene.camera.position, scene.bounds()) if sun else ()
        placed, self._cascade_boxes = self._placement.get((scene.camera.key(), self._mesh.key, s.lpv_resolution, s.grid_levels,
                                      s.grid_phases, s.grid_shift, s.width, s.height, sun), place)
        previous = self._indirect.value.grids if self._indirect.value is not None else None
        return keep_or_move(previous, placed)

    def _indirect_light(self, scene, maps, keys, grids, sources, sources_key, stats):
        """The indirect method of the settings over `grids`, built again when the lights,
        VPL pattern, grids, sources or settings it reads changed; its volumes kept while
        the method and grids are the same."""
        s = self.settings.with_changes(bounces=max(light_bounces(self.settings, scene), 1))
        method = indirect_method(s)
        rooms = self._rooms()
        key = (method.name, tuple(keys), self.vpl_pattern, grids, s.propagation_iterations, s.occlusion,
               sources_key, rooms.key if rooms is not None else None) + method.key(s)
        if key != self._indirect.key:
            indirect = self._indirect.value
            if indirect is None or type(indirect) is not method or indirect.grids != grids:
                self._indirect.clear()
                indirect = method(self.glc, grids, s.grid_phases)
            mesh = self._mesh.value
            indirect.build(maps, mesh, scene.bounds(), s, stats, self.vpl_pattern, sources,
                           lambda: self._receivers.get(scene.geometry_key(), lambda: Receivers(self.glc, scene, mesh)),
                           rooms)
            self._indirect.put(key, indirect)
        return self._indirect.value

    def _sides(self, scene):
        """The sides of the scene's faces that light reaches and the rooms they look into
        (gpu/closed_meshes.py): the last array again where a lamp moved but they did not
        (the G-buffer then stays)."""
        closed = self._closed_meshes.get(scene.enclosure_key(), lambda: ClosedMeshes(scene))
        key = (scene.enclosure_key(), closed.emitters_key(scene))
        if key != self._open_sides.key:
            last = self._open_sides.value[0] if self._open_sides.value is not None else None
            found, rooms = closed.sides_and_rooms(scene)
            same = found is last or found is not None and last is not None and \
                found.shape == last.shape and np.array_equal(found, last)
            self._open_sides.put(key, (last if same else found, rooms))
        return self._open_sides.value[0]

    def _direct_light(self, scene, targets, maps, selection, indirect, drawn, stats):
        """The direct image: the lights' with maps, the point emitters' (the `drawn` ones of
        the scene glowing too) and the emissive surfaces' with their glow."""
        s = self.settings
        rooms = self._rooms()
        with self.glc.timed(stats, "direct_ms"):
            for m in maps:
                shadow = shadow_uniforms(m.rsm.light, s.shadow_taps, self.vpl_pattern)
                room = None if rooms is None else (self._mesh.value.open_sides, m.room)
                cascade = (*m.view_maps, m.rsm)  # finest first: each shades what the finer ones leave
                for finer, rsm in zip((None, *cascade), cascade):
                    shade_direct(self.glc, targets, scene.camera, rsm, s.shadow_bias, shadow,
                                 inside=rsm if rsm is not m.rsm else None, outside=finer, room=room)
        if selection is not None and selection.kept:
            with self.glc.timed(stats, "emitter_light_ms"):
                self._emitter_grid.value.add_light(targets, gbuffer_uniforms(scene.camera), s,
                                                   self._emitter_shadows.value if s.emitter_shadows else None)
        if scene.emission is not None or drawn > 0:
            with self.glc.timed(stats, "emission_ms"):
                if scene.emission is not None:
                    self._emitted_light(scene, targets, indirect)
                render_glow(self.glc, self._mesh.value, scene.camera, targets,
                            (self._emitter_grid.value.emitters, drawn) if drawn else None)
        elif world_lights(scene, self.settings):
            with self.glc.timed(stats, "world_ms"):
                self._emitted_light(scene, targets, indirect)

    def _emitted_light(self, scene, targets, indirect):
        """Add the direct light of the scene's emissive surfaces and its world into the
        direct image, gathered through the indirect method's pixel gather."""
        s = self.settings
        gather = indirect.pixel_gather()
        bind_gbuffer(targets)
        world = [(self._world.emitters, self._world.count)] if world_lights(scene, self.settings) else []
        self._emission.add_light(gather, self._mesh.value, targets, gbuffer_uniforms(scene.camera),
                                 scene.camera.position, s.singularity_bound, self.vpl_pattern, world,
                                 self._room_sides())

    def _composite(self, scene, targets, indirect, sets, display, glowing, stats):
        """The indirect image (the method's per-pixel gather first, when it has one; this
        set averaged with the `sets` - 1 before) and the combined one: direct, indirect
        and with `glowing` the glow; with `display` into the viewport's rows too."""
        s = self.settings
        if indirect.gathers_per_pixel:
            with self.glc.timed(stats, "pixel_gather_ms"):
                bind_gbuffer(targets)
                # the n-th set of a converging frame bounds 1/r² by 1/n as much: the average's bias tends to zero
                # (the later bounces' points hold theirs: shaders/emitter.glsl)
                indirect.gather_pixels(targets, gbuffer_uniforms(scene.camera), scene.camera.position,
                                       s.singularity_bound / sets, self.vpl_pattern, s.singularity_bound,
                                       self._room_sides())
        with self.glc.timed(stats, "indirect_ms"):
            world = None
            if scene.world is not None and not scene.film.transparent:
                world = self._world_light().background_texture(scene.world)
            intensity = s.indirect_intensity if light_bounces(s, scene) > 0 else 0.0  # Light Paths of no bounce
            shade_indirect(self.glc, targets, scene.camera, indirect, len(indirect.levels), s.grid_phases,
                           intensity, display, sets - 1, glow=glowing, world=world,
                           reflections=self._reflection_inputs(scene, indirect), room_sides=self._room_sides())

    def _rooms(self):
        """The Rooms of the scene `_sides` last sorted (gpu/closed_meshes.py); None where it
        has none."""
        return self._open_sides.value[1] if self._open_sides.value is not None else None

    def _room_sides(self):
        """The mesh's sides-and-rooms buffer where the scene has rooms, else None."""
        return self._mesh.value.open_sides if self._rooms() is not None else None

    def _world_light(self):
        if self._world is None:
            self._world = WorldLight(self.glc)
        return self._world

    def _reflection_inputs(self, scene, indirect):
        """What the reflections of glossy surfaces read (gpu/shade.py ReflectionInputs);
        None where no surface is glossy."""
        if scene.specular is None:
            return None
        world = self._world_light().reflection_texture(scene.world) if scene.world is not None else None
        occupancy, layers = indirect.march_occupancy() or (None, ())
        low, high = scene.bounds()
        return ReflectionInputs(world, occupancy, layers, float(np.linalg.norm(high - low)), self.vpl_pattern)

    def _read(self, scene, passes, display_into, display_settings, read, stats):
        """The `passes` read back (with `read`; debug ones drawn first), the combined one's
        coverage, and the viewport's rows into `display_into` (when given)."""
        if read and any(name in DEBUG_PASS_NAMES for name in passes):
            with self.glc.timed(stats, "debug_ms"):
                self.draw_debug_passes(scene, display_settings)
        with self.glc.timed(stats, "readback_ms"):
            images = {name: self.targets.read(name) for name in passes if name != "combined"} if read else {}
            coverage = None
            if read and "combined" in passes:
                combined = self.targets.read_rgba("combined")
                images["combined"], coverage = np.ascontiguousarray(combined[..., :3]), combined[..., 3].copy()
            display = None if display_into is None else self.targets.read_display_into(display_into)
        return {name: images[name] for name in passes if name in images}, coverage, display

    def _statistics(self, scene, maps, lit, selection, indirect, vpl_count, sets, accumulated_vpls):
        s = self.settings
        bounces = light_bounces(s, scene)
        rooms = self._rooms()
        warped = [m.warp for m in maps if m.warp is not None]
        stats = {"warp_status": {name: sum(w.counts[name] for w in warped) for name in STATUS_NAMES}} if warped else {}
        stats.update({
            "method": s.method, "light_methods": [m.method for m in maps], "vpl_count": vpl_count,
            "glossy_vpl_count": sum(m.glossy_vpls.count for m in maps if m.glossy_vpls is not None),
            "vpl_pattern": self.vpl_pattern, "vpl_sets": sets, "accumulated_vpls": accumulated_vpls,
            "lights": len(scene.lights), "mapped_lights": len(lit.mapped), "lights_as_emitters": lit.lights_as_emitters,
            "rooms": rooms.count if rooms is not None else 0,
            "skipped_lights": lit.skipped_lights, "point_emitters": selection.kept if selection else 0,
            "skipped_emitters": selection.skipped if selection else 0, "triangles": scene.triangle_count,
            "dropped_triangles": {**scene.dropped, **({"emitters": selection.dropped} if selection and selection.dropped
                                                      else {})},
            "images": [image.name for image in scene.images],
            "approximated_materials": list(scene.approximated_materials),
            "world": scene.world is not None, "bounces": bounces if indirect.more_bounces else min(bounces, 1),
            "world_approximated": list(scene.world.approximated) if scene.world else [],
            "missing_images": list(scene.missing_images), "rsm_resolution": s.rsm_resolution,
            "rsm_faces": int(sum(m.rsm.face_count for m in maps)), **indirect.statistics(s),
            "image_size": [s.width, s.height], "renderer": self.glc.renderer,
            "software_renderer": self.glc.is_software})
        return stats

    def render_converged(self, scene, settings=None, passes=PASS_NAMES, display_settings=None, stop=None,
                         progress=None):
        """A frame whose indirect light averages VPL sets of patterns 0, 1, 2, ...: as many
        as the settings' `converge_sets`, or while `converge_seconds` last when above zero
        (the first set is always made), or until `stop()` is true; `progress(sets done)`
        after each. Stats: `converge_ms` the time of them all, each stage's ms their sum."""
        s = settings or self.settings
        start = time.perf_counter()
        single = s.converge_seconds <= 0 and s.converge_sets <= 1  # else the passes are read once, at the end
        if not single:
            s = s.refined(self.glc.is_software)
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
            frame.passes, frame.coverage, _ = self._read(scene, passes, None, display_settings, True, spent)
            frame.stats.update({key: value for key, value in spent.items() if key != "total_ms"})
        frame.stats["converge_ms"] = (time.perf_counter() - start) * 1000.0
        return frame

    def _centred_gbuffer(self, scene):
        """The last frame's G-buffer at the pixels' centres, drawn again when its last VPL
        set looked through another point of them: what reads it after a frame (the
        corrections, the debug passes) takes pixel centres."""
        if self._gbuffer_offset:
            render_gbuffer(self.glc, self._mesh.value, scene.camera, self.targets)
            self._gbuffer_offset = False
            self._gbuffer_drawn = None

    def read_gbuffer(self, scene):
        """The last frame's G-buffer as a GBufferRecord (gpu/shade.py), for the corrections."""
        self._centred_gbuffer(scene)
        return read_gbuffer_record(self.glc, self.targets, scene.camera)

    def draw_debug_passes(self, scene, display_settings=None):
        """Draw the last frame's debug passes (DEBUG_PASS_NAMES) into its images."""
        self._centred_gbuffer(scene)
        render_debug_passes(self.glc, self.targets, scene.camera, self.last_light_maps,
                            (display_settings or DisplaySettings()).vpl_point_size)

    def _select_emitters(self, scene, s, lit, box, min_distance, stats):
        """The frame's point emitters (the scene's and the point lights beyond the budget)
        on the GPU, those weakest at `box` skipped: an EmitterSelection, or None without any."""
        if not scene.point_emitter_count and not lit.lights_as_emitters:
            self._emitter_grid.clear()
            return None
        grid = self._emitter_grid.get(grid_resolution(s.emitter_grid_resolution),
                                      lambda: EmitterGrid(self.glc, s.emitter_grid_resolution))
        with self.glc.timed(stats, "emitter_upload_ms"):
            grid.upload(scene.point_emitters, lit.lamp_rows, (scene.point_emitters_key(), lit.key))
        with self.glc.timed(stats, "emitter_select_ms"):
            selection = grid.select(box, min_distance, s.light_cutoff)
        if selection.dropped == scene.point_emitter_count:
            scene.require_lights(point_emitters_lit=False)
        return selection

    def _emitter_sources(self, scene, s, selection, box, grids, stats):
        """Build the emitter grid of the frame's point emitters (when it keeps any) and their
        shadows' light grid over `grids`, and sample the emissive surfaces' emitters; the
        emitters whose light bounces (gpu/emitter_bounce.py EmitterSources), and a key of
        what they hold."""
        sources, bound, key = [], 0.0, ()
        emitting = selection is not None and selection.kept
        if not emitting or not s.emitter_shadows:
            self._emitter_shadows.clear()
        if emitting:
            grid = self._emitter_grid.value
            if s.emitter_light == "grid":
                with self.glc.timed(stats, "emitter_grid_ms"):
                    grid.build(box, s.singularity_bound)
            if s.emitter_shadows:
                shadows = self._emitter_shadows.get(grids, lambda: EmitterShadows(self.glc, grids, s.grid_phases))
                with self.glc.timed(stats, "emitter_shadow_ms"):
                    shadows.build(self._mesh.value, [(grid.emitters, grid.count)], selection.flux_bound,
                                  selection.bounds(scene.bounds()), s.singularity_bound,
                                  (selection.chosen, self._mesh.key, s.singularity_bound))
            sources.append((grid.emitters, grid.count))
            bound += selection.flux_bound
            key += selection.chosen
        if (scene.emission is not None or world_lights(scene, self.settings)) and self._emission is None:
            self._emission = SurfaceEmission(self.glc)
        if scene.emission is not None:
            sides = self._open_sides.value[0] if self._rooms() is not None else None
            self._emission.sample(scene, s.emission_samples, self.vpl_pattern, sides)
            sources.append((self._emission.emitters, self._emission.count))
            bound += self._emission.flux_bound
            key += (scene.geometry_key(), s.emission_samples, None if sides is None else array_key(sides))
        if world_lights(scene, self.settings):
            self._world_light().sample(scene, s.world_samples, self.vpl_pattern)
            sources.append((self._world.emitters, self._world.count))
            bound += self._world.flux_bound
            key += (scene.world.key(), s.world_samples)
        # what the bounce marches through and bounds, whichever method gathers it
        return (EmitterSources(tuple(sources), bound),
                key + ((self._mesh.key, s.emitter_bounce_samples, s.singularity_bound) if sources else ()))

    def gpu_bytes(self):
        """GPU memory the pipeline holds now: mesh, light maps, VPLs, LPV, camera images."""
        held = [*self.vpl_sampler.resources()]
        for cache in (self._mesh, self._indirect, self._emitter_grid, self._emitter_shadows, self._receivers):
            held += cache.value.resources() if cache.value is not None else ()
        held += self._emission.resources() if self._emission is not None else ()
        held += self._world.resources() if self._world is not None else ()
        for maps in self._lights.values():
            held += maps.resources()
        held += self.targets.resources() if self.targets is not None else ()
        return resource_bytes(*held)

    def invalidate(self):
        """Forget every cached stage result, so the next render redoes every stage."""
        for maps in self._lights.values():
            maps.release()
        self._lights.clear()
        self._accumulated = None
        self._gbuffer_drawn = None
        for cache in (self._placement, self._frame_lights, self._receivers, self._closed_meshes, self._open_sides,
                      self._emitter_grid, self._emitter_shadows):
            cache.clear()
        if self._emission is not None:
            self._emission.release()
            self._emission = None
        if self._world is not None:
            self._world.release()
            self._world = None
        if self._indirect.value is not None:
            self._indirect.value.forget()
        self._indirect.forget()  # keep the volumes' memory, forget their content

    def _upload(self, scene, stats):
        def upload():
            with self.glc.timed(stats, "upload_ms"):
                return MeshBuffer(self.glc, scene)
        key = scene.geometry_key()
        self._mesh.get(key, upload)
        return key

    def release(self):
        self.invalidate()
        for cache in (self._indirect, self._mesh, self._targets):
            cache.clear()
        self.vpl_sampler.release()
