"""The light grid: every cell centre gathers the light of every point emitter that sees it.

Where the LPV spreads light cell by cell (and blurs it), the light grid sums at each cell
centre the exact irradiance of every emitter, with visibility through a voxelisation of
the scene, as an ambient cube (the irradiance of six surfaces facing the axes: exact for
them, and no SH ringing that lets a surface light itself). Emitters come as buffers of
the VPL layout (shaders/emitter.glsl): the lights' VPLs now, emissive surfaces and
particles next. They are first summed into clusters, one per block of CLUSTER_CELLS³ cells
of the finest level holding them and normal direction, so the gather's cost follows the
surfaces lit, not the emitter count; the clusters into clusters twice as wide, and so on
up to one per level, and a cell centre gathers the widest ones that are far enough from it
(a light cut), so the cost follows the cells' distance in octaves, not the clusters' count.
"""
import math

import moderngl
import numpy as np

from .closed_meshes import RAY, ROOM_CODE_DEFINES, ROOM_DEFINES, ROOM_TESTS
from .context import dispatch, dispatch_row, run_workgroups, set_uniforms, zero_buffer
from .grids import fit_grid
from .occupancy import LOOP_LIMIT, VOXELS_PER_CELL, Occupancy, march_batch
from .vpl import EMITTER_BYTES

CLUSTER_CELLS = 2
"""The finest cluster of emitters spans this many cells of its level along each side: one
cell is closer to Cycles, but its eight times as many clusters cost llvmpipe's gather more
than the test suite's time allows (docs/method.md)."""
CUT_GRID_CELLS = 32
"""Grids of this many cells a side and more gather a light cut of wider clusters; smaller
ones every finest cluster, which costs the H100 as little and llvmpipe less (docs/method.md)."""
NEAR_SIZES = 1.5
"""A cluster stands for its emitters at cell centres farther than NEAR_SIZES times its width
from its cell; nearer, the clusters half as wide inside it do (docs/method.md)."""
BINS = 13  # a cluster's lobe: a cosine normal's main axis and sign, none, or a glossy lobe's axis and sign
CLUSTER_INTS = 12
"""flux rgb, weighted place xyz, weighted normal (or glossy axis) xyz, weight, weight whose bound is held (a glossy
cluster's: weight over lobe exponent), area"""
FIXED_POINT_RANGE = 2.0 ** 30
AREA_UNITS = 1 << 16
"""Fixed-point units of a cluster's area sum per area of a finest cluster cell."""
MEMBER_AREA_CAP = 256
"""The most finest cluster cells' area one emitter adds to a cluster's: 2^31 units hold 128
such emitters, and no light map's VPL stands for that much of one cell."""
CELL_ROOM_TESTS = 1 << 28
"""Cell centres tested against a room's walls, every grid's cells times every room's walls,
at most on a GPU (on llvmpipe closed_meshes.py ROOM_TESTS): beyond it the grid keeps
rooms apart nowhere (a room of a million walls would take seconds)."""
DIRECTIONS = 6  # +x, -x, +y, -y, +z, -z
GATHER_LANES = 64  # invocations sharing one cell's emitters (shaders/light_grid_gather.comp)
LIGHT_GRID_BYTES_PER_CELL = DIRECTIONS * 16
"""Six RGBA32F irradiances (its occupancy: gpu/occupancy.py occupancy_bytes)."""
COUNT_BYTES = 64  # the clusters' total, then where each octave starts in the list
CLUSTER_BYTES = 4 + CLUSTER_INTS * 4 + EMITTER_BYTES + 1  # per hash slot: key, sums, emitter, its block's count


def cluster_capacity(emitter_total):
    """Slots of a hash table of clusters of `emitter_total` emitters: a power of two, at
    least twice the emitters, at most 2^20."""
    return min(1 << max(10, math.ceil(math.log2(max(2 * emitter_total, 1)))), 1 << 20)


def cluster_tables(emitter_total, cluster_size, levels, room_count=1):
    """Slots of each octave's hash table, finest first (the finest alone for grids under
    CUT_GRID_CELLS), for `levels` cluster grids of `cluster_size` cells a side: twice the
    clusters it can hold, which are no more than the emitters and no more than the cells
    times the normals' bins times the `room_count` rooms kept apart (a million particles in a 16³
    grid's levels make a few thousand clusters at most)."""
    tables = []
    octaves = cluster_size.bit_length() if cluster_size * CLUSTER_CELLS >= CUT_GRID_CELLS else 1
    for octave in range(octaves):
        cells = levels * BINS * room_count * (((cluster_size - 1) >> octave) + 1) ** 3
        tables.append(min(cluster_capacity(emitter_total), 1 << max(6, math.ceil(math.log2(2 * cells)))))
    return tables


def cluster_bytes(emitter_total, settings):
    """What the clusters of `emitter_total` emitters take over the grids of `settings`."""
    return sum(cluster_tables(emitter_total, max(1, settings.lpv_resolution // CLUSTER_CELLS),
                              settings.grid_levels + 1)) * CLUSTER_BYTES


def cluster_levels(levels, scene_bounds):
    """The grids emitters are clustered over for `levels` (finest first): each level's
    coarser by CLUSTER_CELLS, and a last one over the scene that holds every emitter."""
    grids = [grid.coarser(CLUSTER_CELLS) for grid in levels]
    return grids + [fit_grid(scene_bounds, grids[0].size)]


def _block_words(slots):
    """A hash table's block counts (emitter_compact.comp), padded to 256 bytes: each
    octave's are bound at an offset, which GL wants aligned."""
    return max(-(-slots // 64), 64)


class LightGrid:
    """The irradiance volumes and occupancy of a set of grids (levels x phases) and the
    emitter clusters they gather from; with `unshadowed`, volumes of the light without
    occluders beside them."""

    def __init__(self, glc, grids, unshadowed=False):
        self.glc = glc
        self.grids = tuple(grids)
        gl = glc.gl
        n = self.grids[0].size
        self.irradiance, self.unshadowed = [], []
        for volumes in (self.irradiance, self.unshadowed) if unshadowed else (self.irradiance,):
            for _ in self.grids:
                volume = gl.texture3d((n, n, DIRECTIONS * n), 4, dtype="f4")
                volume.filter = (moderngl.NEAREST, moderngl.NEAREST)
                volumes.append(volume)
        self.occupancy = Occupancy(glc, self.grids)
        # the cells a lookup can read, marked per mesh (shaders/light_grid_receiving.comp), with their rooms
        self.receiving = gl.texture3d((n, n, n * len(self.grids)), 1, dtype="u1")
        self._no_cells = bytes(n ** 3 * len(self.grids))
        self.marked = None  # the mesh `receiving` was marked from
        self.rooms_marked = None  # the rooms' key and whether `receiving` holds their rooms, since it was marked
        self.count = gl.buffer(reserve=COUNT_BYTES)
        self.keys = self.sums = self.blocks = self.emitters = None  # each octave's table one after another
        self.tables = []
        self.cluster_uniforms = {}

    def _cluster_buffers(self, tables):
        if tables != self.tables:
            for buffer in (self.keys, self.sums, self.blocks, self.emitters):
                if buffer is not None:
                    buffer.release()
            gl = self.glc.gl
            self.keys = gl.buffer(reserve=sum(tables) * 4)
            self.sums = gl.buffer(reserve=sum(tables) * CLUSTER_INTS * 4)
            self.blocks = gl.buffer(reserve=sum(_block_words(slots) for slots in tables) * 4)
            self.emitters = gl.buffer(reserve=sum(tables) * EMITTER_BYTES)
            self.tables = tables
        for buffer in (self.keys, self.sums, self.count):
            zero_buffer(self.glc, buffer)

    def cluster(self, emitter_sets, flux_bound, cluster_grids, room_count=1):
        """Sum the emitters (buffers with counts) into clusters of `cluster_grids` (the
        levels, finest first, and a last grid that holds every emitter), with a
        `room_count` over 1 apart by the room each lies in (gpu/closed_meshes.py), then
        those into clusters twice as wide, octave after octave, all in one list."""
        size = cluster_grids[0].size
        tables = cluster_tables(sum(count for _, count in emitter_sets), size, len(cluster_grids), room_count)
        self._cluster_buffers(tables)
        defines = {"LEVELS": len(cluster_grids), "CLUSTER_INTS": CLUSTER_INTS, "DEPTH": len(tables), "CLUSTER_BINS": BINS,
                   "AREA_UNITS": AREA_UNITS, "MEMBER_AREA_CAP": MEMBER_AREA_CAP,
                   **(ROOM_DEFINES if room_count > 1 else ROOM_CODE_DEFINES)}
        levels = {"level_origins": np.array([g.origin for g in cluster_grids]),
                  "level_cells": np.array([g.cell_size for g in cluster_grids]), "grid_size": size,
                  "flux_scale": FIXED_POINT_RANGE / flux_bound if flux_bound > 0 else 1.0}
        self.count.bind_to_storage_buffer(3)
        first_slot = first_block = 0
        for octave, slots in enumerate(tables):
            program = self.glc.compute("emitter_cluster", WIDER=int(octave > 0), **defines)
            set_uniforms(program, capacity=slots, octave=octave, **levels)
            self.keys.bind_to_storage_buffer(1, offset=first_slot * 4, size=slots * 4)
            self.sums.bind_to_storage_buffer(2, offset=first_slot * CLUSTER_INTS * 4, size=slots * CLUSTER_INTS * 4)
            if octave == 0:
                for buffer, count in emitter_sets:
                    buffer.bind_to_storage_buffer(0)
                    dispatch_row(program, count, "first_emitter", emitter_count=count)
            else:  # the octave before's clusters
                self.emitters.bind_to_storage_buffer(0)
                dispatch_row(program, tables[octave - 1], "first_emitter")
            self.emitters.bind_to_storage_buffer(0)
            self.blocks.bind_to_storage_buffer(4, offset=first_block * 4, size=_block_words(slots) * 4)
            for stage in range(3):
                program = self.glc.compute("emitter_compact", STAGE=stage, **defines)
                set_uniforms(program, capacity=slots, octave=octave, **levels)
                dispatch(program, 1 if stage == 1 else slots, local=(64,))
            first_slot += slots
            first_block += _block_words(slots)
        self.cluster_uniforms = {"cluster_origins": levels["level_origins"], "cluster_cells": levels["level_cells"],
                                 "cluster_grid_size": size}

    def cluster_count(self):
        """The clusters of every octave the last `cluster` listed (a read that waits for it)."""
        return int(np.frombuffer(self.count.read(size=4), dtype=np.int32)[0])

    def _mark_receiving(self, mesh):
        """Mark the cells within reach of the lookups at `mesh`'s surfaces, in every grid."""
        self.receiving.write(self._no_cells)
        self.receiving.bind_to_image(0, read=False, write=True)
        mesh.buffer.bind_to_storage_buffer(0)
        program = self.glc.compute("light_grid_receiving")
        for layer, grid in enumerate(self.grids):
            dispatch_row(program, mesh.triangle_count, "first_triangle", grid_origin=grid.origin,
                         cell_size=grid.cell_size, grid_size=grid.size, layer=layer, triangle_count=mesh.triangle_count)
        self.marked = mesh
        self.rooms_marked = None

    def mark_cells(self, rooms=None):
        """Mark the cells a lookup can read, once per mesh, and with `rooms`
        (gpu/closed_meshes.py Rooms) each one's room: the innermost holding its centre
        (shaders/light_grid_rooms.comp); whether the rooms are marked. Not where the
        tests would pass CELL_ROOM_TESTS (on llvmpipe ROOM_TESTS, or its loop limit in one
        cell): the grid then keeps rooms apart nowhere."""
        if self.marked is not self.occupancy.voxelised:
            self._mark_receiving(self.occupancy.voxelised)
        if rooms is None:
            return False
        if self.rooms_marked is not None and self.rooms_marked[0] == rooms.key:
            return self.rooms_marked[1]
        walls, firsts, counts, lows, highs = rooms.walls()
        tests = sum(grid.size ** 3 for grid in self.grids) * len(walls)
        affordable = tests <= ROOM_TESTS and len(walls) <= LOOP_LIMIT if self.glc.is_software else \
            tests <= CELL_ROOM_TESTS
        self.rooms_marked = (rooms.key, affordable)
        if not self.rooms_marked[1]:
            return False
        buffer = self.glc.gl.buffer(walls.tobytes())
        program = self.glc.compute("light_grid_rooms", **ROOM_CODE_DEFINES)
        padded = {name: np.resize(values, (ROOM_CODE_DEFINES["ROOM_CODES"],) + values.shape[1:])
                  for name, values in (("first_wall", firsts), ("wall_count", counts), ("room_low", lows),
                                       ("room_high", highs))}
        self.marked.buffer.bind_to_storage_buffer(0)
        buffer.bind_to_storage_buffer(1)
        self.receiving.bind_to_image(0, read=True, write=True)
        for layer, grid in enumerate(self.grids):
            set_uniforms(program, **padded, room_count=len(counts), ray=tuple(float(v) for v in RAY),
                         grid_origin=grid.origin, cell_size=grid.cell_size, grid_size=grid.size, layer=layer)
            dispatch(program, grid.size ** 3, local=(64,))
        buffer.release()
        return True

    def gather(self, singularity_bound, levels, rooms_apart=False):
        """Every grid's cells gather the clustered emitters' light through the occupancy's
        levels (`levels`: the layer of each, finest first) and its outer grid, each from its
        own grid's level on, in batches of emitters whose marches stay under llvmpipe's loop
        limit (shaders/light_grid_gather.comp), its 1/r² bounded by `singularity_bound`
        (shaders/emitter.glsl); with `rooms_apart` (clustered apart, the cells' rooms
        marked: mark_cells) each cell only from the clusters of its own room."""
        self.mark_cells()
        levels = list(levels)
        phases = len(self.grids) // len(levels)
        layers = self.occupancy.march_layers(levels)
        program = self.glc.compute("light_grid_gather", UNSHADOWED=int(bool(self.unshadowed)), MARCH_LEVELS=len(layers),
                                   CLUSTER_LEVELS=len(self.cluster_uniforms["cluster_cells"]), DEPTH=len(self.tables),
                                   NEAR_SIZES=NEAR_SIZES, CLUSTER_BINS=BINS, **(ROOM_DEFINES if rooms_apart else ROOM_CODE_DEFINES))
        self.emitters.bind_to_storage_buffer(0)
        self.count.bind_to_storage_buffer(1)
        if self.glc.is_software:  # llvmpipe ends long loop nests: batches its limit allows, as many as there are
            count = self.cluster_count()
            batch = march_batch(self.occupancy.voxels, len(layers), GATHER_LANES)
        else:  # one dispatch, which stops at the count: the host does not wait for it
            count = batch = max(sum(self.tables), 1)
        self.receiving.use(location=2)  # after the occupancy's two volumes
        set_uniforms(program, batch=batch, singularity_bound=singularity_bound, receiving=2, **self.cluster_uniforms)
        for layer, (grid, irradiance) in enumerate(zip(self.grids, self.irradiance)):
            irradiance.bind_to_image(0, read=True, write=True)
            if self.unshadowed:
                self.unshadowed[layer].bind_to_image(1, read=True, write=True)
            level = layer // phases  # its own grid's voxels stand for its level: its centres are their centres
            set_uniforms(program, **self.occupancy.march_uniforms((*layers[:level], layer, *layers[level + 1:]),
                                                                  first_unit=0),
                         grid_origin=grid.origin, cell_size=grid.cell_size, grid_size=grid.size, first_level=level,
                         layer=layer)
            for first in range(0, max(count, 1), batch):
                set_uniforms(program, first_emitter=first)
                run_workgroups(program, grid.size ** 3)  # a workgroup per cell

    def lookup_uniforms(self, first_unit, paired=False):
        """Bind the volumes for shaders/light_grid_lookup.glsl from texture unit `first_unit`
        on; `paired`, the unshadowed ones too (its PAIRED lookup)."""
        units = len(self.grids)
        volumes = [*self.irradiance, *(self.unshadowed if paired else ())]
        for i, volume in enumerate(volumes):
            volume.use(location=first_unit + i)
        after = first_unit + len(volumes)
        self.occupancy.occupancy.use(location=after)
        self.occupancy.coarse.use(location=after + 1)
        uniforms = {"light_grid": np.arange(first_unit, first_unit + units), "occupancy": after, "coarse": after + 1,
                    "voxels_per_cell": VOXELS_PER_CELL}
        if paired:
            uniforms["unshadowed_grid"] = np.arange(first_unit + units, after)
        return uniforms

    def read_irradiance(self, index):
        """Grid `index`'s irradiance as (direction, z, y, x, rgb) float32, the directions
        +x, -x, +y, -y, +z, -z."""
        n = self.grids[index].size
        data = np.frombuffer(self.irradiance[index].read(), dtype=np.float32)
        return data.reshape(DIRECTIONS, n, n, n, 4)[..., :3]

    def resources(self):
        buffers = [b for b in (self.keys, self.sums, self.emitters, self.blocks) if b is not None]
        return (*self.irradiance, *self.unshadowed, *self.occupancy.resources(), self.receiving, self.count, *buffers)

    def release(self):
        self.occupancy.release()
        clusters = (b for b in (self.keys, self.sums, self.emitters, self.blocks) if b is not None)
        for resource in (*self.irradiance, *self.unshadowed, self.receiving, self.count, *clusters):
            resource.release()
