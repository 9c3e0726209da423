"""The light grid: every cell centre gathers the light of every point emitter that sees it.

Where the LPV spreads light cell by cell (and blurs it), the light grid sums at each cell
centre the exact irradiance of every emitter, with visibility through a voxelisation of
the scene, as an ambient cube (the irradiance of six surfaces facing the axes: exact for
them, and no SH ringing that lets a surface light itself). Emitters come as buffers of
the VPL layout (shaders/emitter.glsl): the lights' VPLs now, emissive surfaces and
particles next. They are first summed into clusters, one per block of CLUSTER_CELLS³ cells
of the finest level holding them and normal direction, so the gather's cost follows the
surfaces lit, not the emitter count.
"""
import math

import moderngl
import numpy as np

from .context import dispatch, set_uniforms

VOXELS_PER_CELL = 3
"""Occupancy voxels along a cell's side: odd, so a cell centre is a voxel's centre, and
enough that a wall thinner than a cell lies between the cells on its two sides."""
CLUSTER_CELLS = 2
"""A cluster of emitters spans this many cells of its level along each side: a quarter to
an eighth as many clusters to gather as with one cell, for little loss (docs/method.md)."""
CLUSTER_INTS = 10  # flux rgb, weighted place xyz, weighted normal xyz, weight
EMITTER_BYTES = 48
FIXED_POINT_RANGE = 2.0 ** 30
DIRECTIONS = 6  # +x, -x, +y, -y, +z, -z
MARCH_STEP = 0.7  # voxels, as in shaders/occupancy.glsl
LOOP_LIMIT = 60000  # llvmpipe stops a loop nest after 65,535 iterations
GATHER_LANES = 64  # invocations sharing one cell's emitters (shaders/light_grid_gather.comp)


def cluster_capacity(emitter_total):
    """Slots of the clusters' hash table: a power of two, at least twice the emitters (no
    more clusters than emitters), at most 2^20 (more clusters than surface cells to fill)."""
    return min(1 << max(10, math.ceil(math.log2(max(2 * emitter_total, 1)))), 1 << 20)


def axis_projections(grid):
    """Orthographic view-projections that map the grid's box onto clip space looking along
    x, y and z: the voxelisation draws each triangle along the one its normal is closest to."""
    side = grid.cell_size * grid.size
    scale = np.diag([2.0 / side] * 3 + [1.0])
    scale[:3, 3] = -1.0 - 2.0 * np.asarray(grid.origin) / side
    swaps = (np.array([1, 2, 0]), np.array([2, 0, 1]), np.array([0, 1, 2]))
    projections = []
    for order in swaps:
        permute = np.zeros((4, 4))
        permute[3, 3] = 1.0
        permute[np.arange(3), order] = 1.0
        projections.append(permute @ scale)
    return projections


class LightGrid:
    """The irradiance volumes and occupancy of a set of grids (levels x phases) and the
    emitter clusters they gather from."""

    def __init__(self, glc, grids):
        self.glc = glc
        self.grids = tuple(grids)
        gl = glc.gl
        n = self.grids[0].size
        self.voxels = n * VOXELS_PER_CELL
        self.irradiance = []
        for _ in self.grids:
            volume = gl.texture3d((n, n, DIRECTIONS * n), 4, dtype="f4")
            volume.filter = (moderngl.NEAREST, moderngl.NEAREST)
            self.irradiance.append(volume)
        # Every grid's voxels and cells, one grid after the other along z.
        self.occupancy = gl.texture3d((self.voxels, self.voxels, self.voxels * len(self.grids)), 1, dtype="u1")
        self.coarse = gl.texture3d((n, n, n * len(self.grids)), 1, dtype="u1")
        for volume in (self.occupancy, self.coarse):
            volume.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self._empty = bytes(self.voxels ** 3 * len(self.grids))
        self._empty_coarse = bytes(n ** 3 * len(self.grids))
        self._canvas = gl.renderbuffer((self.voxels, self.voxels), 1, dtype="f1")
        self._framebuffer = gl.framebuffer(color_attachments=[self._canvas])
        self.large = gl.buffer(reserve=3 * 4)  # the large triangles' vertex indices, grown as needed
        self.command = gl.buffer(reserve=5 * 4)
        self.count = gl.buffer(reserve=16)
        self.keys = self.sums = self.emitters = self.blocks = None
        self.capacity = 0
        self.emitter_count = 0

    def voxelise(self, mesh):
        """Mark the voxels the lights' triangles pass through, in every grid: the small
        triangles sampled in a compute pass, the large ones it lists rasterised."""
        gl = self.glc.gl
        first, count = mesh.light_triangles
        if self.large.size < 3 * 4 * max(count, 1):
            self.large.release()
            self.large = gl.buffer(reserve=3 * 4 * max(count, 1))
        self.occupancy.write(self._empty)
        self.coarse.write(self._empty_coarse)
        self.occupancy.bind_to_image(0, read=False, write=True)
        self.coarse.bind_to_image(1, read=False, write=True)
        program = self.glc.compute("voxelise_small", GRIDS=len(self.grids))
        for binding, buffer in enumerate((mesh.buffer, self.command, self.large)):
            buffer.bind_to_storage_buffer(binding)
        set_uniforms(program, grid_origins=np.array([grid.origin for grid in self.grids]),
                     voxel_sizes=np.array([grid.cell_size / VOXELS_PER_CELL for grid in self.grids]),
                     voxels=self.voxels, voxels_per_cell=VOXELS_PER_CELL, first_triangle=first,
                     triangle_count=count, reset=True)
        dispatch(program, 5, local=(64,))
        set_uniforms(program, reset=False)
        dispatch(program, count, local=(64,))
        program = self.glc.program("raster", "occupancy", geometry="occupancy")
        self._framebuffer.viewport = (0, 0, self.voxels, self.voxels)
        self._framebuffer.use()
        gl.disable(moderngl.DEPTH_TEST)
        gl.disable(moderngl.CULL_FACE)
        for layer, grid in enumerate(self.grids):
            set_uniforms(program, grid_origin=grid.origin, voxel_size=grid.cell_size / VOXELS_PER_CELL,
                         voxels_per_cell=VOXELS_PER_CELL, voxels=self.voxels, layer=layer,
                         view_projection=np.eye(4), axis_projections=np.array(axis_projections(grid)))
            mesh.vertex_array(program, self.large).render_indirect(self.command, moderngl.TRIANGLES, count=1)
        gl.memory_barrier()

    def _cluster_buffers(self, emitter_total):
        capacity = cluster_capacity(emitter_total)
        if capacity != self.capacity:
            for buffer in (self.keys, self.sums, self.emitters, self.blocks):
                if buffer is not None:
                    buffer.release()
            gl = self.glc.gl
            self.blocks = gl.buffer(reserve=-(-capacity // 64) * 4)
            self.keys = gl.buffer(reserve=capacity * 4)
            self.sums = gl.buffer(reserve=capacity * CLUSTER_INTS * 4)
            self.emitters = gl.buffer(reserve=capacity * EMITTER_BYTES)
            self.capacity = capacity
        self.keys.write(np.full(capacity, -1, dtype=np.int32).tobytes())
        self.sums.clear()
        self.count.clear()

    def cluster(self, emitter_sets, flux_bound, cluster_grids):
        """Sum the emitters (buffers with counts) into clusters of `cluster_grids` (the
        levels, finest first, and a last grid that holds every emitter)."""
        total = sum(count for _, count in emitter_sets)
        self._cluster_buffers(total)
        defines = {"LEVELS": len(cluster_grids), "CLUSTER_INTS": CLUSTER_INTS}
        levels = {"level_origins": np.array([g.origin for g in cluster_grids]),
                  "level_cells": np.array([g.cell_size for g in cluster_grids]),
                  "grid_size": cluster_grids[0].size, "capacity": self.capacity,
                  "flux_scale": FIXED_POINT_RANGE / flux_bound if flux_bound > 0 else 1.0}
        program = self.glc.compute("emitter_cluster", **defines)
        self.keys.bind_to_storage_buffer(1)
        self.sums.bind_to_storage_buffer(2)
        for buffer, count in emitter_sets:
            buffer.bind_to_storage_buffer(0)
            set_uniforms(program, emitter_count=count, **levels)
            dispatch(program, count, local=(64,))
        for binding, buffer in enumerate((self.emitters, self.keys, self.sums, self.count, self.blocks)):
            buffer.bind_to_storage_buffer(binding)
        for stage in range(3):
            program = self.glc.compute("emitter_compact", STAGE=stage, **defines)
            set_uniforms(program, **levels)
            dispatch(program, 1 if stage == 1 else self.capacity, local=(64,))

    def gather(self):
        """Every grid's cells gather the clustered emitters' light, in batches of emitters
        whose marches stay under llvmpipe's loop limit (shaders/light_grid_gather.comp)."""
        program = self.glc.compute("light_grid_gather")
        self.emitters.bind_to_storage_buffer(0)
        self.count.bind_to_storage_buffer(1)
        self.emitter_count = int(np.frombuffer(self.count.read(size=4), dtype=np.int32)[0])
        longest_march = math.ceil(self.voxels * math.sqrt(3) / MARCH_STEP) + 1
        batch = GATHER_LANES * max(1, LOOP_LIMIT // longest_march)
        self.occupancy.use(location=0)
        self.coarse.use(location=1)
        for layer, (grid, irradiance) in enumerate(zip(self.grids, self.irradiance)):
            irradiance.bind_to_image(0, read=True, write=True)
            set_uniforms(program, occupancy=0, coarse=1, layer=layer, grid_origin=grid.origin,
                         cell_size=grid.cell_size, grid_size=grid.size, voxels_per_cell=VOXELS_PER_CELL, batch=batch)
            for first in range(0, max(self.emitter_count, 1), batch):
                set_uniforms(program, first_emitter=first)
                dispatch(program, grid.size ** 3, local=(1,))  # a workgroup per cell

    def lookup_uniforms(self, first_unit):
        """Bind the volumes for shaders/light_grid_lookup.glsl from texture unit `first_unit` on."""
        units = len(self.grids)
        for i, volume in enumerate(self.irradiance):
            volume.use(location=first_unit + i)
        self.occupancy.use(location=first_unit + units)
        self.coarse.use(location=first_unit + units + 1)
        return {"light_grid": np.arange(first_unit, first_unit + units), "occupancy": first_unit + units,
                "coarse": first_unit + units + 1,
                "voxels_per_cell": VOXELS_PER_CELL}

    def read_irradiance(self, index):
        """Grid `index`'s irradiance as (direction, z, y, x, rgb) float32, the directions
        +x, -x, +y, -y, +z, -z."""
        n = self.grids[index].size
        data = np.frombuffer(self.irradiance[index].read(), dtype=np.float32)
        return data.reshape(DIRECTIONS, n, n, n, 4)[..., :3]

    def resources(self):
        buffers = [b for b in (self.keys, self.sums, self.emitters, self.blocks) if b is not None]
        return (*self.irradiance, self.occupancy, self.coarse, self._canvas, self.large, self.command, self.count,
                *buffers)

    def release(self):
        self._framebuffer.release()
        for resource in self.resources():
            resource.release()
