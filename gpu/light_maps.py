"""Each light's reflective shadow maps and VPLs: how a method of Table 1 makes them, what
`auto` chooses, and for a sun over a large scene the map of the region the grids cover."""
from dataclasses import dataclass

import numpy as np

from .frame_lights import seen_box
from .rsm import PROJECTION_PARABOLOID, cube_face_count, render_rsm, sun_half_width
from .warp import STATUS_NAMES, warp_paraboloid_map


# `auto` tessellates a light's paraboloids when this share of the texels that found
# geometry is still failed or only approximate after WDPM (docs/method.md, "auto").
AUTO_TESSELLATION_SHARE = 0.10
AUTO_METHODS = ("cm", "wdpm", "twdpm")  # what `auto` may choose for a light


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

GLOSSY_VPL_SHARE = 0.125
"""In a scene with glossy layers, each light gets this share of its VPL count again as
glossy VPLs, which carry what the layers reflect along their lobes (gpu/vpl.py): a
layer reflects 4-15 % of a dielectric's light, a metal's all of it."""


@dataclass
class LightMaps:
    """One light's RSM (warped for WDPM), its VPLs, the method that made them, for the
    warped methods the warp status, and for a sun whose map spans far more than the camera
    sees, the map of the region it sees (`region`, the box `region_box`) that the VPLs come
    from, with `far_vpls` from the whole map outside it; in a scene with glossy layers
    `glossy_vpls` of what they reflect (the region's, for such a sun); and the Poisson pattern of the
    VPLs (gpu/vpl.py); for a sun, the cascade of maps its direct light looks up where the
    camera looks (`view_maps` of the boxes `view_boxes`: fit_view_maps); the room the light
    lies in, which its VPLs carry (gpu/closed_meshes.py); the least GGX alpha of its glossy
    VPLs' lobes (gpu/vpl.py glossy_blur_alpha)."""

    rsm: object
    method: str
    warp: object = None
    region: object = None
    region_box: tuple = None
    vpls: object = None
    far_vpls: object = None
    glossy_vpls: object = None
    pattern: int = None
    view_maps: tuple = ()
    view_boxes: tuple = None
    room: int = 0
    least_glossy_alpha: float = 0.0

    def fit_view_maps(self, glc, mesh, resolution, boxes, bounds, stats):
        """A sun's cascade of maps for its direct light, finest first: one fitted across
        its rays to each of `boxes` (cascade_boxes), each reaching every occluder of
        `bounds` along the rays, `resolution` texels a side; made again when the boxes or
        the resolution change. A box gets a map
        only where its texels are VIEW_MAP_GAIN times smaller than those of the next
        coarser map (the coarsest's: the whole map)."""
        if (boxes, resolution) == self.view_boxes:
            return
        for view_map in self.view_maps:
            view_map.release()
        self.view_boxes, fitted = (boxes, resolution), []
        coarser = self.rsm.ortho_texel
        for box in reversed(boxes):
            corners = tuple(np.array(corner) for corner in box)
            texel = 2 * sun_half_width(self.rsm.light, corners, True) / resolution
            if texel > 1e-9 and texel * VIEW_MAP_GAIN <= coarser:
                with glc.timed(stats, "rsm_ms"):
                    fitted.append(render_rsm(glc, mesh, self.rsm.light, resolution, corners, reach=bounds,
                                             fitted=True))
                coarser = texel
        self.view_maps = tuple(reversed(fitted))

    @property
    def vpl_map(self):
        """The map the VPLs were sampled from."""
        return self.region if self.region is not None else self.rsm

    def sample_vpls(self, sampler, count, pattern):
        """(Re)sample the VPLs (and a sun's far field) in Poisson pattern `pattern`."""
        for vpls in self.vpl_sets():
            vpls.release()
        self.vpls = sampler.sample(self.vpl_map, count, pattern, room=self.room)
        self.far_vpls = None if self.region is None else sampler.sample(
            self.rsm, max(1, int(count * FAR_FIELD_SHARE)), pattern, exclude=self.region_box, room=self.room)
        self.glossy_vpls = None if not self.vpl_map.glossy else sampler.sample(
            self.vpl_map, max(1, int(count * GLOSSY_VPL_SHARE)), pattern, room=self.room, glossy=True,
            least_alpha=self.least_glossy_alpha)
        self.pattern = pattern

    def vpl_sets(self):
        """The light's VPL sets (gpu/vpl.py VPLSet)."""
        return [vpls for vpls in (self.vpls, self.far_vpls, self.glossy_vpls) if vpls is not None]

    def emitter_sets(self):
        """The light's VPL buffers with their counts, for the indirect stage."""
        return [(vpls.buffer, vpls.count) for vpls in self.vpl_sets()]

    @property
    def flux_bound(self):
        """No channel of the VPLs' summed flux exceeds this: the map's bound, twice it with
        glossy VPLs, which give back what their lobes send below the surface (up to as much
        again: gpu/vpl.py)."""
        return self.vpl_map.flux_bound * (2.0 if self.glossy_vpls is not None else 1.0)

    @property
    def vpl_count(self):
        return sum(count for _, count in self.emitter_sets())

    def resources(self):
        """The GPU memory of the maps, VPLs and warp status."""
        held = (self.rsm.position, self.rsm.normal, self.rsm.flux, *(buffer for buffer, _ in self.emitter_sets()))
        held += (self.warp.texture,) if self.warp is not None else ()
        for extra in (self.region, *self.view_maps):
            held += (extra.position, extra.normal, extra.flux) if extra is not None else ()
        return held

    def release(self):
        for resource in (self.rsm, *self.vpl_sets(), self.warp, self.region, *self.view_maps):
            if resource is not None:
                resource.release()


VIEW_MAP_GAIN = 1.5
"""A grid level's box gets a map of a sun's direct light (LightMaps.fit_view_maps) when
that map's texels are at least this many times smaller than the next coarser map's."""

SUN_CASCADES = 3
CASCADE_NEAR_SHARE = 0.05
"""A sun's direct-light cascade splits the distances from the camera to the points it sees
geometrically, from this quantile of them to the farthest, into SUN_CASCADES ranges."""

CASCADE_MARGIN = 0.06
"""Each cascade box grows by this share of its size on every side: the points it bounds
stay within the part of its map that shades them (gpu/shade.py VIEW_MAP_EDGE)."""


def cascade_boxes(points, eye, bounds, count=SUN_CASCADES):
    """The boxes of a sun's direct-light cascade, finest first, as a hashable tuple of
    pairs of tuples: the i-th bounds the points the camera sees (`points`, (k, 3); the
    G-buffer sampled) up to the i-th split distance from the eye, within the scene's
    `bounds`, so each holds the finer ones. Empty when it sees too few."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if len(points) < 8:
        return ()
    distance = np.linalg.norm(points - np.asarray(eye, dtype=np.float64), axis=1)
    near, far = max(float(np.quantile(distance, CASCADE_NEAR_SHARE)), 1e-6), float(distance.max())
    boxes = []
    for i in range(1, count + 1):
        held = points[distance <= near * (far / near) ** (i / count) * (1 + 1e-9)]
        margin = CASCADE_MARGIN * float(np.max(held.max(axis=0) - held.min(axis=0)))
        low = np.maximum(held.min(axis=0) - margin, bounds[0])
        high = np.minimum(held.max(axis=0) + margin, bounds[1])
        boxes.append((tuple(map(float, low)), tuple(map(float, np.maximum(high, low)))))
    return tuple(boxes)


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


def render_light_maps(glc, mesh, light, settings, bounds, stats, sampler, pattern, region=None, room=0,
                      least_glossy_alpha=0.0):
    """A light's LightMaps by the settings' method, its VPLs in Poisson pattern `pattern`
    and in the light's `room` (gpu/closed_meshes.py), its glossy VPLs' lobes at least
    `least_glossy_alpha` wide (gpu/vpl.py glossy_blur_alpha); `auto` tessellates where its first
    choice leaves too many texels unresolved."""
    args = (glc, mesh, light, settings, bounds, stats, sampler, pattern, region, room, least_glossy_alpha)
    if settings.method != "auto":
        return _render_with(settings.method, *args)
    maps = _render_with(auto_method(light), *args)
    if maps.warp is not None:
        found = sum(maps.warp.counts[name] for name in STATUS_NAMES[1:])
        unresolved = maps.warp.counts["failed"] + maps.warp.counts["approximate"]
        if unresolved > AUTO_TESSELLATION_SHARE * found:
            maps.release()
            maps = _render_with("twdpm", *args)
    return maps


def _render_with(method, glc, mesh, light, s, bounds, stats, sampler, pattern, region, room, least_glossy_alpha):
    recipe = map_recipe(s, method)
    with glc.timed(stats, "rsm_ms"):
        rsm = render_rsm(glc, mesh, light, s.rsm_resolution, bounds, recipe.projection, recipe.tessellation_unit,
                         pattern=pattern)
    status = None
    if recipe.warp_alpha is not None and rsm.projection_kind == PROJECTION_PARABOLOID:
        with glc.timed(stats, "warp_ms"):
            warped, status = warp_paraboloid_map(glc, rsm, recipe.warp_alpha, s.warp_iterations,
                                                 s.warp_significant_figures)
        rsm.release()
        rsm = warped
    region_map = None
    if region is not None:
        with glc.timed(stats, "rsm_ms"):
            region_map = render_rsm(glc, mesh, light, s.rsm_resolution, tuple(np.array(corner) for corner in region),
                                    reach=bounds, pattern=pattern)
    maps = LightMaps(rsm, method, status, region_map, region, room=room, least_glossy_alpha=least_glossy_alpha)
    with glc.timed(stats, "vpl_ms"):
        maps.sample_vpls(sampler, s.vpls_per_light, pattern)
    return maps
