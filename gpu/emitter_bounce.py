"""Light passed on by points on the surfaces: points sampled on the surfaces the lights
see, each lit by a set of emitters through a march over the occupancy
(shaders/emitter_bounce.comp), become VPLs that the indirect stage gathers beside the
lights' own. The emitters (point emitters, emissive surfaces, the world) bounce this way,
and every bounce after the first (gpu/bounces.py)."""
import math
from dataclasses import dataclass

import numpy as np

from .closed_meshes import OPEN, ROOM_CODE_DEFINES
from .context import dispatch, run_workgroups, set_uniforms
from .occupancy import march_batch
from .vpl import EMITTER_BYTES

RECEIVER_SENDERS = 256
"""Senders each receiver gathers from per set: a strided subset (scaled up), so the cost is
this many marches a receiver, whatever the sender count; converging frames change the
subset."""
LANES = 64  # invocations sharing one receiver's senders (shaders/emitter_bounce.comp)
RECEIVER_BYTES = 2 * EMITTER_BYTES + 32  # a receiver's row, its VPL and its irradiance while lit
RECEIVER_TRIANGLE_BYTES = 20  # a light triangle's cumulative area share and bounce colour (Receivers)


def flux_bound(rows):
    """The largest channel of the summed flux of emitter rows ((N, 3, 4) as
    shaders/emitter.glsl lays them out) made on the host."""
    return float(rows[:, 2, :3].sum(axis=0, dtype=np.float64).max()) if len(rows) else 0.0


@dataclass
class EmitterSources:
    """The emitter sets whose light bounces ((buffer, count) pairs: the point emitters, the
    emissive surfaces' samples, the world's directions) and a bound on any channel of the
    flux of theirs that reaches the surfaces, known on the host (their rows are made or
    counted there; the world's emitters stand far off: gpu/world.py SCENE_SHARE)."""

    sets: tuple = ()
    flux_bound: float = 0.0

    def __bool__(self):
        return bool(self.sets)


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
    """The triangles the lights see, held on the GPU to be sampled in proportion to area
    (shaders/receiver_draw.comp): their cumulative area shares and the colours they bounce,
    RECEIVER_TRIANGLE_BYTES a triangle; `mesh` (gpu/mesh_buffer.py, of the scene) holds their
    corners and the sides of them light reaches."""

    def __init__(self, glc, scene, mesh):
        first, total = scene.light_triangles
        self.glc, self.mesh, self.first, self.total = glc, mesh, first, total
        colours = scene.surface_colours(first, total)
        self.largest_albedo = colours.max(axis=0) if total else np.zeros(3, dtype=np.float32)
        corners = scene.triangles[first:first + total].astype(np.float64)
        doubled = np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
        self.area = float(doubled.sum()) / 2
        self.cumulative = self.colours = None
        if self.area > 0:
            self.cumulative = glc.gl.buffer((np.cumsum(doubled) / doubled.sum()).astype(np.float32).tobytes())
            padded = np.zeros((total, 4), dtype=np.float32)
            padded[:, :3] = colours
            self.colours = glc.gl.buffer(padded.tobytes())

    def draw(self, count, pattern):
        """(buffer, count) of `count` receivers (shaders/emitter_bounce.comp Receiver) drawn
        with the random numbers of `pattern`, light reaching the sides the mesh's
        `open_sides` hold now, in the rooms they hold; (None, 0) where the lights see no surface."""
        mesh = self.mesh
        if self.cumulative is None or count < 1:
            return None, 0
        buffer = self.glc.gl.buffer(reserve=count * EMITTER_BYTES)  # a Receiver is as long as an Emitter
        program = self.glc.compute("receiver_draw", OPEN=OPEN)
        sides = mesh.open_sides if mesh.open_sides is not None else self.cumulative  # bound, not read
        for binding, source in enumerate((mesh.positions, self.cumulative, self.colours, sides, buffer)):
            source.bind_to_storage_buffer(binding)
        set_uniforms(program, count=count, triangles=self.total, first=self.first, seed=pattern & 0xFFFFFFFF,
                     area_each=self.area / count, sides_known=mesh.open_sides is not None)
        dispatch(program, count, local=(64,))
        return buffer, count

    def resources(self):
        return tuple(b for b in (self.cumulative, self.colours) if b is not None)

    def release(self):
        for buffer in self.resources():
            buffer.release()
        self.cumulative = self.colours = None


def light_receivers(glc, receivers, emitter_sets, occupancy, singularity_bound, pattern, flux_bound,
                    senders_per_receiver=RECEIVER_SENDERS):
    """The receivers ((buffer, count) of `Receivers.draw`, the buffer released here) lit by
    the emitter sets ((buffer, count) pairs), each receiver gathering a strided subset of
    `senders_per_receiver` of each set, marching every grid of `occupancy`, each side
    only from the senders that light its room (gpu/closed_meshes.py): an EmitterVPLs,
    each in its brighter side's room, whose flux bound is `flux_bound` (gpu/bounces.py
    conserve holds their flux to it on the GPU: nothing is read back)."""
    gl = glc.gl
    layers = occupancy.every_grid_layers()
    receiver_buffer, count = receivers
    if not count:
        receiver_buffer, count = gl.buffer(np.zeros((1, 3, 4), dtype=np.float32).tobytes()), 1
    irradiance = gl.buffer(reserve=count * 32)
    lit = gl.buffer(reserve=count * EMITTER_BYTES)
    program = glc.compute("emitter_bounce", MARCH_LEVELS=len(layers), LANES=LANES, **ROOM_CODE_DEFINES)
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
    return EmitterVPLs(lit, count, flux_bound)
