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
    gap = np.maximum(np.maximum(low - positions, positions - high), 0.0)
    return intensity / np.maximum(np.einsum("ij,ij->i", gap, gap), np.float32(min_distance ** 2))


def skip_weak(bound, cutoff):
    """A mask of the emitters to keep, given their `light_bounds`: those dropped, the
    weakest, give together at most `cutoff` of the sum of the bounds. The threshold comes
    from a histogram of the bounds weighted by themselves, not a sort: a million emitters
    take a pass, and a little less than `cutoff` may be dropped."""
    total = float(bound.sum(dtype=np.float64))
    keep = np.ones(len(bound), dtype=bool)
    if cutoff <= 0 or not total > 0:
        return keep
    positive = bound[bound > 0].astype(np.float64)
    edges = np.geomspace(positive.min(), positive.max() * (1 + 1e-9), SKIP_BINS + 1)
    weights, _ = np.histogram(positive, bins=edges, weights=positive)
    below = np.concatenate([[0.0], np.cumsum(weights)])  # the zeros are dropped first: they add nothing
    threshold = edges[np.searchsorted(below, cutoff * total, side="right") - 1]
    keep &= bound >= threshold
    return keep


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
    intensity = np.concatenate([np.array([light.peak_intensity @ luminance for light in lights], np.float32),
                                emitters[:, 3:6] @ luminance / np.float32(4 * np.pi)])
    positions = np.concatenate([np.array([light.position for light in lights], np.float32).reshape(-1, 3),
                                emitters[:, :3]])
    strength = light_bounds(positions, intensity, box, min_distance)
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
    rows, placed = emitters, positions[len(lights):]
    if not kept_emitters.all():
        rows, placed = emitters[kept_emitters], placed[kept_emitters]
    if extra:
        lamps = np.array([[*light.position, *light.rgb_power, np.pi * light.radius ** 2] for light in extra],
                         dtype=np.float32)
        rows, placed = np.concatenate([rows, lamps]), np.concatenate([placed, lamps[:, :3]])
    key = (scene.point_emitters_key(), np.packbits(kept_emitters).tobytes(), tuple(light.key() for light in extra))
    flux_bound = float(rows[:, 3:6].sum(axis=0, dtype=np.float64).max()) if len(rows) else 0.0
    emitter_box = (placed.min(axis=0), placed.max(axis=0)) if len(placed) else None
    return FrameLights(mapped, rows, key, flux_bound, len(lights) - len(kept_lights), int((~kept_emitters).sum()),
                       len(extra), emitter_box)
