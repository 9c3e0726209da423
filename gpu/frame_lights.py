"""What lights a frame: the lights that get maps and the point lights beyond the light-map
budget, the weakest at the view skipped. Bounds of each light's irradiance at the box the
camera sees rank them (docs/method.md, "Many emitters"); the scene's point emitters are
ranked the same way on the GPU (gpu/emitter_grid.py select)."""
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
    """A mask of the lamps to keep, given their `light_bounds`: those dropped, the weakest,
    give together at most `cutoff` of the sum of the bounds. The threshold comes from a
    histogram of the bounds in logarithmic bins weighted by themselves, as the point
    emitters' on the GPU (shaders/emitter_select.comp): a little less than `cutoff` may be
    dropped."""
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
    """What lights a frame of the scene's lamps: the lights that get maps, the point lights
    beyond the budget as point-emitter rows ((k, 7) float32 as gpu/scene.py holds point
    emitters) with their keys, and counts. The scene's own point emitters are chosen on the
    GPU (gpu/emitter_grid.py select)."""

    mapped: list
    lamp_rows: np.ndarray
    key: tuple
    skipped_lights: int
    lights_as_emitters: int


def frame_lights(scene, settings, box, min_distance):
    """Split the scene's lamps for a frame looking at `box`: the weakest there, together
    under `light_cutoff` of the lamps' light, are skipped (a sun never is); of the point
    lights left, the `light_map_budget` strongest get maps and the rest become point
    emitters. The scene's point emitters are skipped by the same rule among themselves, so
    what both drop stays under `light_cutoff` of all the light."""
    lights = scene.lights
    luminance = LUMINANCE_WEIGHTS.astype(np.float32)
    strength = light_bounds(np.array([light.position for light in lights], np.float32).reshape(-1, 3),
                            np.array([light.peak_intensity @ luminance for light in lights], np.float32),
                            box, min_distance)
    sun = np.array([light.kind == "SUN" for light in lights], dtype=bool)
    keep = skip_weak(np.where(sun, 0.0, strength).astype(np.float32), settings.light_cutoff) | sun
    kept_lights = [i for i in range(len(lights)) if keep[i]]
    points = sorted((i for i in kept_lights if lights[i].kind == "POINT"), key=lambda i: -strength[i])
    as_emitters = set(points[settings.light_map_budget:])
    mapped = [lights[i] for i in kept_lights if i not in as_emitters]
    extra = [lights[i] for i in sorted(as_emitters)]
    rows = np.array([[*light.position, *light.rgb_power, np.pi * light.radius ** 2] for light in extra],
                    dtype=np.float32).reshape(-1, POINT_EMITTER_COLUMNS)
    return FrameLights(mapped, rows, tuple(light.key() for light in extra), len(lights) - len(kept_lights),
                       len(extra))
