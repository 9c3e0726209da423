"""More bounces: the VPLs lit by one another, generation by generation (shaders/bounce.comp).

Generation g + 1 lies where the first does and carries the light generation g gives it
times the surface's albedo; the indirect stage gathers from one set per light whose flux
is the sum of every generation's, so a frame of two bounces or eight costs the gather
no more than one. Light reaches the surfaces only through the places the lights' maps
see: a surface no light sees directly passes nothing on.
"""
import math

from .context import set_uniforms
from .occupancy import march_batch
from .vpl import GATHER_ROW

RECEIVER_SENDERS = 256
"""Senders each VPL gathers from per bounce: a random subset (scaled up), so the cost is
this many marches a VPL, whatever the VPL count; converging frames change the subset."""
LANES = 64  # invocations sharing one receiver's senders (shaders/bounce.comp)
EMITTER_BYTES = 48


class Bounces:
    """Each light's VPLs with every generation's flux summed (`sets`), and the buffers the
    generations pass through."""

    def __init__(self, glc):
        self.glc = glc
        self.sets = []      # (buffer, count) per light: the totals
        self._scratch = []

    def build(self, maps, bounces, occupancy, layers, singularity_bound, pattern):
        """Light each light's VPLs (`maps`: pipeline.LightMaps) by every light's, `bounces`
        - 1 times over, marching `occupancy`'s grids `layers` (indices, finest first);
        returns the totals."""
        self.release()
        gl = self.glc.gl
        counts = [m.vpls.count for m in maps]
        self.sets = [(gl.buffer(reserve=count * EMITTER_BYTES), count) for count in counts]
        for (total, count), m in zip(self.sets, maps):
            gl.copy_buffer(total, m.vpls.buffer)
        irradiance = [gl.buffer(reserve=count * 16) for count in counts]
        generations = [[gl.buffer(reserve=count * EMITTER_BYTES) for count in counts] for _ in range(2)]
        self._scratch = irradiance + generations[0] + generations[1]
        stride = max(1, math.ceil(sum(counts) / RECEIVER_SENDERS))
        program = self.glc.compute("bounce", LEVELS=len(layers))
        batch = march_batch(occupancy.voxels, len(layers), LANES * stride)
        set_uniforms(program, **occupancy.march_uniforms(list(layers), first_unit=0), batch=batch, stride=stride,
                     singularity_bound=singularity_bound)
        senders = [m.vpls.buffer for m in maps]
        for bounce in range(1, bounces):
            made = generations[bounce % 2]
            for light, m in enumerate(maps):
                m.vpls.buffer.bind_to_storage_buffer(1)
                irradiance[light].bind_to_storage_buffer(2)
                made[light].bind_to_storage_buffer(3)
                self.sets[light][0].bind_to_storage_buffer(4)
                set_uniforms(program, receiver_count=counts[light], pattern=pattern * bounces + bounce,
                             **m.vpl_map.light_uniforms)
                steps = [(buffer, n, first) for buffer, n in zip(senders, counts) for first in range(0, n, batch)]
                for step, (buffer, n, first) in enumerate(steps):
                    buffer.bind_to_storage_buffer(0)
                    set_uniforms(program, sender_count=n, first_sender=first, accumulate=step > 0,
                                 finish=step == len(steps) - 1)
                    program.run(min(counts[light], GATHER_ROW), -(-counts[light] // GATHER_ROW), 1)
                    gl.memory_barrier()
            senders = made
        return self.sets

    def resources(self):
        return (*self._scratch, *(buffer for buffer, _ in self.sets))

    def release(self):
        for resource in self.resources():
            resource.release()
        self.sets, self._scratch = [], []
