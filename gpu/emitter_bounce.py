"""Light passed on by points on the surfaces: points sampled on the surfaces the lights
see, each lit by a set of emitters through a march over the occupancy
(shaders/emitter_bounce.comp), become VPLs that the indirect stage gathers beside the
lights' own. The emitters (point emitters, emissive surfaces, the world) bounce this way,
and every bounce after the first (gpu/bounces.py)."""
import math
from dataclasses import dataclass

import numpy as np

from .closed_meshes import OPEN
from .context import run_workgroups, set_uniforms
from .occupancy import march_batch
from .surface_emitters import TrianglePoints
from .vpl import EMITTER_BYTES

RECEIVER_SENDERS = 256
"""Senders each receiver gathers from per set: a strided subset (scaled up), so the cost is
this many marches a receiver, whatever the sender count; converging frames change the
subset."""
LANES = 64  # invocations sharing one receiver's senders (shaders/emitter_bounce.comp)
RECEIVER_BYTES = 2 * EMITTER_BYTES + 32  # a receiver's row, its VPL and its irradiance while lit


@dataclass
class EmitterVPLs:
    """The receivers as VPLs: a buffer of shaders/emitter.glsl rows, their count and a
    bound on any channel's total flux."""

    buffer: object
    count: int
    flux_bound: float

    def release(self):
        self.buffer.release()


class Receivers:
    """The triangles the lights see, ready to be sampled in proportion to area."""

    def __init__(self, scene):
        first, total = scene.light_triangles
        self.first = first
        self.albedo = scene.surface_colours(first, total)
        self.points = None if total == 0 else TrianglePoints(
            scene.triangles[first:first + total].astype(np.float64), lambda doubled: doubled)

    def rows(self, count, pattern, sides=None):
        """(count, 3, 4) float32 receiver rows (shaders/emitter_bounce.comp Receiver) drawn
        with the random numbers of `pattern` (none when the lights see no surface):
        position, face normal and the area each stands for, and the triangle's mean colour
        (its texture's too) with the sides of it light can reach (gpu/closed_meshes.py, of
        the scene's triangles `sides`; None: both)."""
        if self.points is None:
            return np.zeros((0, 3, 4), dtype=np.float32)
        picked, positions = self.points.draw(count, pattern)
        rows = np.zeros((count, 3, 4), dtype=np.float32)
        rows[:, 0, :3], rows[:, 0, 3] = positions, 1.0
        rows[:, 1, :3] = self.points.cross[picked] / self.points.doubled_area[picked, None]
        rows[:, 1, 3] = self.points.doubled_area.sum() / 2 / count
        rows[:, 2, :3] = self.albedo[picked]
        rows[:, 2, 3] = OPEN if sides is None else sides[self.first + picked]
        return rows


def light_receivers(glc, receivers, emitter_sets, occupancy, singularity_bound, pattern,
                    senders_per_receiver=RECEIVER_SENDERS, flux_bound=None):
    """The receivers (rows of `Receivers.rows`) lit by the emitter sets ((buffer,
    count) pairs), each receiver gathering a strided subset of `senders_per_receiver` of
    each set, marching every grid of `occupancy`: an EmitterVPLs whose flux bound is
    `flux_bound` where given, else their flux read back and summed."""
    gl = glc.gl
    layers = occupancy.every_grid_layers()
    count = max(len(receivers), 1)
    if not len(receivers):
        receivers = np.zeros((1, 3, 4), dtype=np.float32)
    receiver_buffer = gl.buffer(receivers.tobytes())
    irradiance = gl.buffer(reserve=count * 32)
    lit = gl.buffer(reserve=count * EMITTER_BYTES)
    program = glc.compute("emitter_bounce", MARCH_LEVELS=len(layers), LANES=LANES)
    set_uniforms(program, **occupancy.march_uniforms(layers, first_unit=0), singularity_bound=singularity_bound,
                 receiver_count=count, pattern=pattern)
    receiver_buffer.bind_to_storage_buffer(1)
    irradiance.bind_to_storage_buffer(2)
    lit.bind_to_storage_buffer(3)
    passes = [(buffer, senders, first, stride, batch)
              for buffer, senders in emitter_sets if senders
              for stride in [max(1, math.ceil(senders / senders_per_receiver))]
              for batch in [march_batch(occupancy.voxels, len(layers), LANES * stride)]
              for first in range(0, senders, batch)]
    for number, (buffer, senders, first, stride, batch) in enumerate(passes):
        buffer.bind_to_storage_buffer(0)
        set_uniforms(program, sender_count=senders, first_sender=first, stride=stride, batch=batch,
                     accumulate=number > 0, finish=number == len(passes) - 1)
        run_workgroups(program, count)
    for buffer in (receiver_buffer, irradiance):
        buffer.release()
    if not passes:
        lit.write(np.zeros((count, 3, 4), dtype=np.float32).tobytes())
    if flux_bound is None:
        flux_bound = float(np.frombuffer(lit.read(), dtype=np.float32).reshape(count, 3, 4)[:, 2, :3].sum(axis=0).max())
    return EmitterVPLs(lit, count, flux_bound)
