"""More bounces: each light's VPLs lit by one another, generation by generation
(shaders/bounce.comp).

Generation g + 1 lies where the first does and carries the light generation g gives it
times the surface's albedo; the indirect stage gathers from one set per light whose flux
is the sum of every generation's, so a frame of two bounces or eight costs the gather
no more than one. Each light's light bounces through the places its own map sees (light
is additive, and two lights' VPLs on one surface would count its bounce twice): a
surface a light does not see passes none of that light's on.
"""
import math

from .context import run_workgroups, set_uniforms
from .occupancy import march_batch
from .vpl import EMITTER_BYTES

RECEIVER_SENDERS = 256
"""Senders each VPL (and each receiver of the emitters' bounce, gpu/emitter_bounce.py)
gathers from per bounce and set: a strided subset (scaled up), so the cost is this many
marches a VPL, whatever the VPL count; converging frames change the subset."""
LANES = 64  # invocations sharing one receiver's senders (shaders/bounce.comp, emitter_bounce.comp)
BOUNCE_SCRATCH_BYTES_PER_VPL = 16 + 2 * EMITTER_BYTES  # received irradiance, two generations


class Bounces:
    """Each light's VPLs with every generation's flux summed (`sets`)."""

    def __init__(self, glc):
        self.glc = glc
        self.sets = []  # (buffer, count) per light: the totals

    def build(self, maps, bounces, occupancy, layers, singularity_bound, pattern):
        """Light each light's VPLs (`maps`: light_maps.LightMaps) by one another, `bounces` - 1
        times over, marching `occupancy`'s grids `layers` (indices, finest first); returns
        the totals."""
        self.release()
        gl = self.glc.gl
        program = self.glc.compute("bounce", LEVELS=len(layers), LANES=LANES)
        set_uniforms(program, **occupancy.march_uniforms(list(layers), first_unit=0),
                     singularity_bound=singularity_bound)
        for m in maps:
            count = m.vpls.count
            total = gl.buffer(reserve=count * EMITTER_BYTES)
            gl.copy_buffer(total, m.vpls.buffer)
            self.sets.append((total, count))
            stride = max(1, math.ceil(count / RECEIVER_SENDERS))
            batch = march_batch(occupancy.voxels, len(layers), LANES * stride)
            irradiance = gl.buffer(reserve=count * 16)
            generations = [gl.buffer(reserve=count * EMITTER_BYTES) for _ in range(2)]
            m.vpls.buffer.bind_to_storage_buffer(1)
            irradiance.bind_to_storage_buffer(2)
            total.bind_to_storage_buffer(4)
            set_uniforms(program, receiver_count=count, sender_count=count, stride=stride, batch=batch,
                         **m.vpl_map.light_uniforms)
            senders = m.vpls.buffer
            for bounce in range(1, bounces):
                made = generations[bounce % 2]
                senders.bind_to_storage_buffer(0)
                made.bind_to_storage_buffer(3)
                set_uniforms(program, pattern=pattern * bounces + bounce)
                firsts = range(0, count, batch)
                for first in firsts:
                    set_uniforms(program, first_sender=first, accumulate=first > 0, finish=first == firsts[-1])
                    run_workgroups(program, count)
                senders = made
            for buffer in (irradiance, *generations):
                buffer.release()
        return self.sets

    def resources(self):
        return tuple(buffer for buffer, _ in self.sets)

    def release(self):
        for resource in self.resources():
            resource.release()
        self.sets = []
