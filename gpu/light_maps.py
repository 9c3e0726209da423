"""Each light's reflective shadow maps and VPLs: how a method of Table 1 makes them, what
`auto` chooses, and for a sun over a large scene the map of the region the grids cover."""
from dataclasses import dataclass

import numpy as np

from .frame_lights import seen_box
from .rsm import PROJECTION_PARABOLOID, cube_face_count, render_rsm
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
    def direct_map(self):
        """The map the direct light's shadows are looked up in."""
        return self.rsm

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


def render_light_maps(glc, mesh, light, settings, bounds, stats, sampler, pattern, region=None):
    """A light's LightMaps by the settings' method, its VPLs in Poisson pattern `pattern`;
    `auto` tessellates where its first choice leaves too many texels unresolved."""
    if settings.method != "auto":
        return _render_with(settings.method, glc, mesh, light, settings, bounds, stats, sampler, pattern, region)
    maps = _render_with(auto_method(light), glc, mesh, light, settings, bounds, stats, sampler, pattern, region)
    if maps.warp is not None:
        found = sum(maps.warp.counts[name] for name in STATUS_NAMES[1:])
        unresolved = maps.warp.counts["failed"] + maps.warp.counts["approximate"]
        if unresolved > AUTO_TESSELLATION_SHARE * found:
            maps.release()
            maps = _render_with("twdpm", glc, mesh, light, settings, bounds, stats, sampler, pattern, region)
    return maps


def _render_with(method, glc, mesh, light, s, bounds, stats, sampler, pattern, region):
    recipe = map_recipe(s, method)
    with glc.timed(stats, "rsm_ms"):
        rsm = render_rsm(glc, mesh, light, s.rsm_resolution, bounds, recipe.projection, recipe.tessellation_unit)
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
                                    reach=bounds)
    maps = LightMaps(rsm, method, status, region_map, region)
    with glc.timed(stats, "vpl_ms"):
        maps.sample_vpls(sampler, s.vpls_per_light, pattern)
    return maps
