"""More bounces: generation by generation, points drawn anew on the surfaces the lights
see, each lit by the whole generation before (every light's VPLs and the emitters'
bounce together, through the occupancy: gpu/emitter_bounce.py light_receivers), become
VPLs the indirect stage gathers beside the first generation.

Unlike VPLs lit by one another, the points lie wherever the surfaces are, so the second
bounce reaches what no light's map sees (the shadowed side of a sunlit room), and light
that several lights bring to one surface bounces once (docs/method.md, "Bounces").
"""
import numpy as np

from .context import dispatch, set_uniforms
from .emitter_bounce import light_receivers

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


def generation_points(samples, bounce):
    """The points of bounce `bounce`'s generation: `samples` over 2^bounce (at least
    `samples` over 2^bounce rounded up, all of them where that leaves fewer than two), each
    standing for as much more area: a later generation carries less light, so fewer
    points draw it as well."""
    factor = 2 ** bounce
    return samples if samples < 2 * factor else -(-samples // factor)


def conserve(glc, totals, generation, senders, largest_albedo, senders_bound=None):
    """Scale a generation's flux down, channel by channel, to at most its senders' total
    (summed on the GPU, or `senders_bound` where the host knows a bound on it) times their
    receivers' `largest_albedo` (light cannot grow from bounce to bounce), on the GPU
    (shaders/flux_total.comp, flux_conserve.comp; `totals` a buffer of two vec4s). Only the
    faces of a slab thinner than a voxel, whose points the occupancy lights on the same
    side, carry more (docs/method.md, "Bounces")."""
    program = glc.compute("flux_total")
    totals.bind_to_storage_buffer(1)
    sums = [(1, [(generation.buffer, generation.count)])]
    if senders_bound is None:  # one workgroup sums each set: fine for a generation, slow for a million particles
        sums.insert(0, (0, senders))
    else:
        totals.write(np.full(4, senders_bound, dtype=np.float32).tobytes())
    for slot, sets in sums:
        for number, (buffer, count) in enumerate(sets):
            buffer.bind_to_storage_buffer(0)
            set_uniforms(program, row_count=count, slot=slot, accumulate=number > 0)
            dispatch(program, 1, local=(1,))  # one workgroup sums the rows
    program = glc.compute("flux_conserve")
    generation.buffer.bind_to_storage_buffer(0)
    set_uniforms(program, row_count=generation.count, largest_albedo=tuple(float(a) for a in largest_albedo))
    dispatch(program, generation.count, local=(64,))


class Generations:
    """The light's later generations as EmitterVPLs (`made`), the second first."""

    def __init__(self, glc):
        self.glc = glc
        self.made = []
        self.totals = None  # conserve's sums (`sums`), made on first use

    @property
    def flux_bound(self):
        return sum(generation.flux_bound for generation in self.made)

    def build(self, first, first_bound, bounces, receivers, samples, occupancy, singularity_bound, pattern):
        """Generations 2 to `bounces` from the `first` one's (buffer, count) sets, whose flux
        no channel's total exceeds `first_bound`, each on the points `receivers.draw` gives
        (gpu/emitter_bounce.py Receivers: `generation_points(samples, bounce)` of them, drawn
        on the GPU), marching `occupancy`'s grids, each side lit only from its room
        (gpu/closed_meshes.py); returns their (buffer, count) sets.
        Nothing is read back: a generation's bound is the one before's times the largest
        albedo of the surfaces its points are drawn on, which `conserve` holds it to."""
        self.drop()
        senders, bound = list(first), first_bound
        largest_albedo = receivers.largest_albedo
        for bounce in range(1, bounces):
            points = receivers.draw(generation_points(samples, bounce), generation_seed(pattern, bounce))
            bound *= float(largest_albedo.max())
            generation = light_receivers(self.glc, points, senders, occupancy, singularity_bound,
                                         pattern * MAX_BOUNCES + bounce, bound, LATER_SENDERS)
            conserve(self.glc, self.sums(), generation, senders, largest_albedo)
            self.made.append(generation)
            senders = [(generation.buffer, generation.count)]
        return [(generation.buffer, generation.count) for generation in self.made]

    def sums(self):
        """The two vec4s `conserve` sums a generation's and its senders' flux into (the
        emitters' bounce's too: gpu/indirect.py), made on first use."""
        if self.totals is None:
            self.totals = self.glc.gl.buffer(reserve=2 * 16)
        return self.totals

    def resources(self):
        return tuple(generation.buffer for generation in self.made) + ((self.totals,) if self.totals else ())

    def drop(self):
        """Let the generations made go."""
        for generation in self.made:
            generation.release()
        self.made = []

    def release(self):
        self.drop()
        if self.totals is not None:
            self.totals.release()
            self.totals = None
