"""A second bounce: a second generation of VPLs, where the first generation lies, lit by
the first generation's light (shaders/second_bounce.comp). The indirect stage then takes
both generations as emitters, so the light that reaches the surfaces has bounced once
or twice, as in Cycles' full global illumination less the third bounce on."""
import math

from .context import set_uniforms
from .occupancy import march_batch
from .vpl import GATHER_ROW

RECEIVER_SENDERS = 256
"""First-generation VPLs each receiver gathers from: a random subset (scaled up), so the
cost is this many marches a VPL, whatever the VPL count; converging frames change it."""
LANES = 64  # invocations sharing one receiver's senders (shaders/second_bounce.comp)


class SecondBounce:
    """The second-generation VPL buffers of each light, and the irradiance each first
    VPL received."""

    def __init__(self, glc):
        self.glc = glc
        self.sets = []         # (buffer, count) per light
        self._irradiance = []

    def build(self, maps, occupancy, layers, singularity_bound, pattern):
        """Light a copy of each light's VPLs (`maps`: pipeline.LightMaps) by every light's
        VPLs, marching `occupancy`'s grids `layers` (finest first); returns the sets."""
        self.release()
        gl = self.glc.gl
        senders = [(m.vpls.buffer, m.vpls.count) for m in maps]
        total = sum(count for _, count in senders)
        stride = max(1, math.ceil(total / RECEIVER_SENDERS))
        program = self.glc.compute("second_bounce", LEVELS=len(layers))
        batch = march_batch(occupancy.voxels, len(layers), LANES * stride)
        set_uniforms(program, **occupancy.march_uniforms(list(layers), first_unit=0), batch=batch,
                     stride=stride, pattern=pattern, singularity_bound=singularity_bound)
        for m in maps:
            count = m.vpls.count
            irradiance, second = gl.buffer(reserve=count * 16), gl.buffer(reserve=count * 48)
            self._irradiance.append(irradiance)
            self.sets.append((second, count))
            m.vpls.buffer.bind_to_storage_buffer(1)
            irradiance.bind_to_storage_buffer(2)
            second.bind_to_storage_buffer(3)
            set_uniforms(program, receiver_count=count, **m.vpl_map.light_uniforms)
            steps = [(buffer, n, first) for buffer, n in senders for first in range(0, n, batch)]
            for step, (buffer, n, first) in enumerate(steps):
                buffer.bind_to_storage_buffer(0)
                set_uniforms(program, sender_count=n, first_sender=first, accumulate=step > 0,
                             finish=step == len(steps) - 1)
                program.run(min(count, GATHER_ROW), -(-count // GATHER_ROW), 1)
                gl.memory_barrier()
        return self.sets

    def resources(self):
        return (*self._irradiance, *(buffer for buffer, _ in self.sets))

    def release(self):
        for resource in self.resources():
            resource.release()
        self.sets, self._irradiance = [], []
