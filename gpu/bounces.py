"""More bounces: generation by generation, points drawn anew on the surfaces the lights
see, each lit by the whole generation before (every light's VPLs and the emitters'
bounce together, through the occupancy: gpu/emitter_bounce.py light_receivers), become
VPLs the indirect stage gathers beside the first generation.

Unlike VPLs lit by one another, the points lie wherever the surfaces are, so the second
bounce reaches what no light's map sees (the shadowed side of a sunlit room), and light
that several lights bring to one surface bounces once (docs/method.md, "More bounces").
"""
from .emitter_bounce import light_receivers

MAX_BOUNCES = 8  # gpu/settings.py bounces' upper end: each generation draws its points with its own seed


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
            generation = light_receivers(self.glc, receivers(generation_seed(pattern, bounce)), senders, occupancy,
                                         layers, singularity_bound, pattern * MAX_BOUNCES + bounce)
            self.made.append(generation)
            senders = [(generation.buffer, generation.count)]
        return [(generation.buffer, generation.count) for generation in self.made]

    def resources(self):
        return tuple(generation.buffer for generation in self.made)

    def release(self):
        for generation in self.made:
            generation.release()
        self.made = []
