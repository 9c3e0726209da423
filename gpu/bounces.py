"""More bounces: generation by generation, points drawn anew on the surfaces the lights
see, each lit by the whole generation before (every light's VPLs and the emitters'
bounce together, through the occupancy: gpu/emitter_bounce.py light_receivers), become
VPLs the indirect stage gathers beside the first generation.

Unlike VPLs lit by one another, the points lie wherever the surfaces are, so the second
bounce reaches what no light's map sees (the shadowed side of a sunlit room), and light
that several lights bring to one surface bounces once (docs/method.md, "More bounces").
"""
import numpy as np

from .emitter_bounce import light_receivers
from .vpl import EMITTER_BYTES

MAX_BOUNCES = 8  # gpu/settings.py bounces' upper end: each generation draws its points with its own seed
LATER_SENDERS = 128
"""Senders a later generation's point gathers from per set (the emitters' bounce: 256,
gpu/emitter_bounce.py): half the marches, for light that converging frames average."""


def light_bounces(settings, scene):
    """The diffuse bounces a frame of `scene` carries: the settings' Bounces (0: as many as
    the scene's Light Paths say, 1 where they say nothing) within the Light Paths. 0 (Light
    Paths of no diffuse bounce) shows no indirect light."""
    said = scene.diffuse_bounces
    wanted = settings.bounces or (said if said is not None else 1)
    return wanted if said is None else min(wanted, said)


def generation_seed(pattern, bounce):
    """The random numbers of bounce `bounce`'s points in VPL pattern `pattern`: apart from
    every other generation's and from the emitters' bounce (seeded by the pattern)."""
    return (pattern + 1) * 65536 + bounce


def thinned(points, factor):
    """Every `factor`-th of the points, each standing for `factor` times the area: a later
    generation carries less light, so fewer points draw it as well."""
    if factor <= 1 or len(points) < 2 * factor:
        return points
    kept = points[::factor].copy()
    kept[:, 1, 3] *= len(points) / len(kept)
    return kept


def total_flux(sets):
    """The rgb flux of emitter sets ((buffer, count) pairs) summed, read back."""
    total = np.zeros(3)
    for buffer, count in sets:
        rows = np.frombuffer(buffer.read(count * EMITTER_BYTES), dtype=np.float32).reshape(count, 3, 4)
        total += rows[rows[:, 0, 3] > 0, 2, :3].sum(axis=0)
    return total


def conserve(generation, limit):
    """Scale a generation's flux down, channel by channel, to at most `limit`: the light
    that reaches the surfaces, at most all its senders', times their largest albedo. Only
    the faces of a slab thinner than a voxel, whose points the occupancy lights on the same
    side, carry more (docs/method.md, "Bounces")."""
    rows = np.frombuffer(generation.buffer.read(), dtype=np.float32).reshape(generation.count, 3, 4).copy()
    total = rows[:, 2, :3].sum(axis=0)
    scale = np.where(total > limit, limit / np.maximum(total, 1e-30), 1.0)
    if np.any(scale < 1.0):
        rows[:, 2, :3] *= scale.astype(np.float32)
        generation.buffer.write(rows.tobytes())
        generation.flux_bound = float((total * scale).max())


class Generations:
    """The light's later generations as EmitterVPLs (`made`), the second first."""

    def __init__(self, glc):
        self.glc = glc
        self.made = []

    @property
    def flux_bound(self):
        return sum(generation.flux_bound for generation in self.made)

    def build(self, first, bounces, receivers, occupancy, layers, singularity_bound, pattern):
        """Generations 2 to `bounces` from the `first` one's (buffer, count) sets, each on the
        points `receivers(seed)` gives, marching `occupancy`'s grids `layers`; returns
        their (buffer, count) sets."""
        self.release()
        senders = list(first)
        for bounce in range(1, bounces):
            points = receivers(generation_seed(pattern, bounce))
            points = thinned(points, 2 ** (bounce - 1))
            generation = light_receivers(self.glc, points, senders, occupancy, layers, singularity_bound,
                                         pattern * MAX_BOUNCES + bounce, LATER_SENDERS)
            conserve(generation, total_flux(senders) * (points[:, 2, :3].max(axis=0) if len(points) else 0.0))
            self.made.append(generation)
            senders = [(generation.buffer, generation.count)]
        return [(generation.buffer, generation.count) for generation in self.made]

    def resources(self):
        return tuple(generation.buffer for generation in self.made)

    def release(self):
        for generation in self.made:
            generation.release()
        self.made = []
