"""What lights a frame: the lights that get maps, and the point emitters (the scene's and
the point lights beyond the light-map budget), the weakest at the view skipped. Bounds
of each light's irradiance at the box the camera sees rank them (docs/method.md, "Many
emitters")."""
from dataclasses import dataclass

import numpy as np

from .colour import LUMINANCE_WEIGHTS
from .scene import POINT_EMITTER_COLUMNS

SKIP_BINS = 256  # logarithmic bins of skip_weak's histogram


def light_bounds(positions, intensity, box, min_distance):
    """Each emitter's bound on the irradiance it gives the box `box` (low, high): its
    intensity over the squared distance to the box, at least `min_distance`."""
    low, high = (np.asarray(corner, dtype=np.float32) for corner in box)
    squared = np.zeros(len(positions), dtype=np.float32)
    for axis in range(3):
        along = positions[:, axis]
        gap = np.maximum(low[axis] - along, along - high[axis])
        np.maximum(gap, 0.0, out=gap)
        squared += gap * gap
    return intensity / np.maximum(squared, np.float32(min_distance ** 2))


def skip_weak(bound, cutoff):
    """A mask of the emitters to keep, given their `light_bounds`: those dropped, the
    weakest, give together at most `cutoff` of the sum of the bounds. The threshold comes
    from a histogram of the bounds in logarithmic bins weighted by themselves, not a sort:
    a million emitters take a pass, and a little less than `cutoff` may be dropped."""
    total = float(bound.sum(dtype=np.float64))
    if cutoff <= 0 or not total > 0:
        return np.ones(len(bound), dtype=bool)
    positive = bound > 0
    least, most = float(bound[positive].min()), float(bound.max())
    scale = SKIP_BINS / max(np.log(most * (1 + 1e-9) / least), 1e-30)
    with np.errstate(divide="ignore"):  # the zeros fall below every bin: they add nothing and go first
        bins = np.floor(np.log(np.maximum(bound, np.float32(least)) / np.float32(least)) * np.float32(scale))
    bins = np.where(positive, np.clip(bins, 0, SKIP_BINS - 1), -1).astype(np.int32)
    weights = np.bincount(bins[positive], weights=bound[positive], minlength=SKIP_BINS)
    below = np.concatenate([[0.0], np.cumsum(weights)])
    return bins >= np.searchsorted(below, cutoff * total, side="right") - 1


def seen_box(levels, bounds):
    """The coarsest grid level's box within the scene's bounds: where the camera looks."""
    coarsest = levels[-1]
    low = np.maximum(np.asarray(coarsest.origin), bounds[0])
    high = np.maximum(np.minimum(np.asarray(coarsest.origin) + coarsest.cell_size * coarsest.size, bounds[1]), low)
    return low, high


@dataclass
class FrameLights:
    """What lights a frame: the lights that get maps, the point emitters (the scene's and
    the point lights beyond the budget, (M, 7) float32 as gpu/scene.py holds them) with a
    content key, and counts."""

    mapped: list
    emitters: np.ndarray
    key: tuple
    flux_bound: float
    skipped_lights: int
    skipped_emitters: int
    lights_as_emitters: int

    emitter_box: tuple = None  # (low, high) of the point emitters' positions

    def bounds(self, scene_bounds):
        """The scene's bounds grown to hold the point emitters (which may lie outside it)."""
        if self.emitter_box is None:
            return scene_bounds
        return np.minimum(scene_bounds[0], self.emitter_box[0]), np.maximum(scene_bounds[1], self.emitter_box[1])


def frame_lights(scene, settings, box, min_distance):
    """Split the scene's lights and point emitters for a frame looking at `box`: the
    weakest there, together under `light_cutoff` of the light, are skipped (a sun never
    is); of the point lights left, the `light_map_budget` strongest get maps and the rest
    join the point emitters."""
    lights = scene.lights
    emitters = scene.point_emitters if scene.point_emitters is not None else \
        np.zeros((0, POINT_EMITTER_COLUMNS), np.float32)
    luminance = LUMINANCE_WEIGHTS.astype(np.float32)
    lamp_strength = light_bounds(np.array([light.position for light in lights], np.float32).reshape(-1, 3),
                                 np.array([light.peak_intensity @ luminance for light in lights], np.float32),
                                 box, min_distance)
    columns = np.ascontiguousarray(emitters.T)  # one copy: the rows' seven floats make every column strided
    intensity = sum(columns[3 + channel] * (luminance[channel] / np.float32(4 * np.pi)) for channel in range(3))
    strength = np.concatenate([lamp_strength, light_bounds(columns[:3].T, intensity, box, min_distance)])
    for index, light in enumerate(lights):
        if light.kind == "SUN":
            strength[index] = np.inf
    keep = skip_weak(np.where(np.isinf(strength), 0.0, strength), settings.light_cutoff)
    keep[:len(lights)] |= np.isinf(strength[:len(lights)])
    kept_lights = [i for i in range(len(lights)) if keep[i]]
    points = sorted((i for i in kept_lights if lights[i].kind == "POINT"), key=lambda i: -strength[i])
    as_emitters = set(points[settings.light_map_budget:])
    mapped = [lights[i] for i in kept_lights if i not in as_emitters]
    extra = [lights[i] for i in sorted(as_emitters)]
    kept_emitters = keep[len(lights):]
    rows = emitters if kept_emitters.all() else emitters[kept_emitters]
    flux = columns[3:6].sum(axis=1, dtype=np.float64, where=kept_emitters)
    low = columns[:3].min(axis=1, where=kept_emitters, initial=np.inf)
    high = columns[:3].max(axis=1, where=kept_emitters, initial=-np.inf)
    if extra:
        lamps = np.array([[*light.position, *light.rgb_power, np.pi * light.radius ** 2] for light in extra],
                         dtype=np.float32)
        rows = np.concatenate([rows, lamps])
        flux = flux + lamps[:, 3:6].sum(axis=0, dtype=np.float64)
        low, high = np.minimum(low, lamps[:, :3].min(axis=0)), np.maximum(high, lamps[:, :3].max(axis=0))
    key = (scene.point_emitters_key(), np.packbits(kept_emitters).tobytes(), tuple(light.key() for light in extra))
    flux_bound = float(flux.max()) if len(rows) else 0.0
    emitter_box = (low, high) if len(rows) else None
    return FrameLights(mapped, rows, key, flux_bound, len(lights) - len(kept_lights), int((~kept_emitters).sum()),
                       len(extra), emitter_box)
