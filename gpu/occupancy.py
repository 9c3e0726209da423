"""The scene's surfaces voxelised over a set of grids, for visibility marches
(shaders/occupancy.glsl): the light grid's between emitters and cells and between
surfaces and cells."""
import math

import moderngl
import numpy as np

from .context import dispatch, dispatch_row, set_uniforms
from .grids import fit_grid

VOXELS_PER_CELL = 3
"""Occupancy voxels along a cell's side for the light grid: odd, so a cell centre is a
voxel's centre, and enough that a wall thinner than a cell lies between the cells on its
two sides."""
GATHER_VOXELS_PER_CELL = 6
"""Occupancy voxels along a cell's side for VPL gathering, which keeps no cells of light:
the march decides every pixel's visibility, and coarse voxels thicken what it passes by
(an atrium's arcades, lit through their arches: docs/accuracy.md)."""
MARCH_STEP = 0.7  # voxels between a march's samples, as in shaders/occupancy.glsl
LOOP_LIMIT = 60000  # llvmpipe stops a loop nest after 65,535 iterations in all
LARGE_TRIANGLE_BYTES = 3 * 4  # room to list every triangle as one the voxelisation rasterises


def occupancy_bytes(grids, cells, per_cell):
    """An Occupancy's GPU bytes over `grids` grids of `cells` a side and the scene's grid
    beyond them, with its canvas."""
    return (grids + 1) * cells ** 3 * (per_cell ** 3 + 1) + (per_cell * cells) ** 2


def march_batch(voxels, grids=1, lanes=1):
    """How many emitters one dispatch of a gather may take when `lanes` invocations share
    them and each march crosses up to `grids` grids of `voxels` a side: llvmpipe's loop
    limit over the longest marches."""
    longest = grids * (math.ceil(voxels * math.sqrt(3) / MARCH_STEP) + 1)
    return lanes * max(1, LOOP_LIMIT // longest)


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


class Occupancy:
    """Every grid's voxels (`per_cell` a cell side) and cells (non-zero where any of
    their voxels is), one grid after the other along z in one volume each, and last, where
    surfaces that cast shadows reach beyond the grids, a grid of as many cells over them
    all (`outer`, `outer_layer`): a march leaving the grids still meets the walls beyond
    them (the one behind a camera inside a room)."""

    def __init__(self, glc, grids, per_cell=VOXELS_PER_CELL):
        self.glc = glc
        self.grids = tuple(grids)
        self.per_cell = per_cell
        self.outer = None  # the grid over the voxelised mesh's occluders, where they reach beyond the grids
        gl = glc.gl
        n = self.grids[0].size
        self.voxels = n * per_cell
        layers = len(self.grids) + 1
        self.occupancy = gl.texture3d((self.voxels, self.voxels, self.voxels * layers), 1, dtype="u1")
        self.coarse = gl.texture3d((n, n, n * layers), 1, dtype="u1")
        for volume in (self.occupancy, self.coarse):
            volume.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self._empty = bytes(self.voxels ** 3 * layers)
        self._empty_coarse = bytes(n ** 3 * layers)
        self._canvas = gl.renderbuffer((self.voxels, self.voxels), 1, dtype="f1")
        self._framebuffer = gl.framebuffer(color_attachments=[self._canvas])
        # Nothing is written to the canvas: llvmpipe drops what earlier triangles drew in a
        # tile that a later one covers whole with colour written (their voxels with it),
        # which left a floor under a ceiling with holes a tile wide from 216 voxels a side.
        self._framebuffer.color_mask = (False, False, False, False)
        self.large = gl.buffer(reserve=3 * 4)  # the large triangles' vertex indices, grown as needed
        self.command = gl.buffer(reserve=5 * 4)
        self.voxelised = None  # the mesh the volumes hold

    @property
    def outer_layer(self):
        return len(self.grids)

    def march_layers(self, levels):
        """The layers a march goes through: the levels' (finest first), then the outer one
        where the voxelised mesh has one."""
        return (*levels, self.outer_layer) if self.outer is not None else tuple(levels)

    def every_grid_layers(self):
        """The layers a march goes through where each grid is a level (no phases)."""
        return self.march_layers(range(len(self.grids)))

    def _outer_grid(self, bounds):
        """The grid over `bounds` (the mesh's occluders) where they reach beyond the
        coarsest grids, else None."""
        coarsest = max(grid.cell_size for grid in self.grids)
        low, high = (np.asarray(corner, dtype=np.float64) for corner in bounds)
        beyond = any(np.any(low < grid.origin) or np.any(high > np.asarray(grid.origin) + grid.cell_size * grid.size)
                     for grid in self.grids if grid.cell_size == coarsest)
        return fit_grid(bounds, self.grids[0].size) if beyond else None

    def voxelise(self, mesh):
        """Mark the voxels the lights' triangles pass through, in every grid: the small
        triangles sampled in a compute pass, the large ones it lists rasterised. The mesh
        the volumes already hold is not voxelised again (a new VPL set needs no new
        occupancy) until `forget`."""
        if self.voxelised is mesh:
            return
        self.voxelised = mesh
        self.outer = self._outer_grid(mesh.occluder_bounds)
        grids = (*self.grids, self.outer) if self.outer is not None else self.grids
        gl = self.glc.gl
        first, count = mesh.light_triangles
        if self.large.size < 3 * 4 * max(count, 1):
            self.large.release()
            self.large = gl.buffer(reserve=3 * 4 * max(count, 1))
        self.occupancy.write(self._empty)
        self.coarse.write(self._empty_coarse)
        self.occupancy.bind_to_image(0, read=False, write=True)
        self.coarse.bind_to_image(1, read=False, write=True)
        program = self.glc.compute("voxelise_small", GRIDS=len(grids))
        for binding, buffer in enumerate((mesh.buffer, self.command, self.large)):
            buffer.bind_to_storage_buffer(binding)
        set_uniforms(program, grid_origins=np.array([grid.origin for grid in grids]),
                     voxel_sizes=np.array([grid.cell_size / self.per_cell for grid in grids]),
                     voxels=self.voxels, voxels_per_cell=self.per_cell, first_triangle=first,
                     triangle_count=count, reset=True, first_invocation=0)
        dispatch(program, 5, local=(64,))
        set_uniforms(program, reset=False)
        dispatch_row(program, count, "first_invocation")
        program = self.glc.program("raster", "occupancy", geometry="occupancy")
        self._framebuffer.viewport = (0, 0, self.voxels, self.voxels)
        self._framebuffer.use()
        gl.disable(moderngl.DEPTH_TEST)
        gl.disable(moderngl.CULL_FACE)
        for layer, grid in enumerate(grids):
            set_uniforms(program, grid_origin=grid.origin, voxel_size=grid.cell_size / self.per_cell,
                         voxels_per_cell=self.per_cell, voxels=self.voxels, layer=layer,
                         view_projection=np.eye(4), axis_projections=np.array(axis_projections(grid)))
            mesh.vertex_array(program, self.large).render_indirect(self.command, moderngl.TRIANGLES, count=1)
        gl.memory_barrier()


    def forget(self):
        """Voxelise the next mesh asked for, whichever it is."""
        self.voxelised = None

    def march_uniforms(self, layers, first_unit):
        """Bind the volumes from texture unit `first_unit` on; the uniforms of
        shaders/levels_march.glsl marching the grids `layers` (indices, finest first; the
        outer grid's is `outer_layer`)."""
        self.occupancy.use(location=first_unit)
        self.coarse.use(location=first_unit + 1)
        every = (*self.grids, self.outer)
        grids = [every[layer] for layer in layers]
        return {"occupancy": first_unit, "coarse": first_unit + 1,
                "level_origins": np.array([grid.origin for grid in grids]),
                "level_voxels": np.array([grid.cell_size / self.per_cell for grid in grids]),
                "level_layers": np.array(layers, dtype=np.int32), "voxels": self.voxels,
                "voxels_per_cell": self.per_cell}

    def resources(self):
        return (self.occupancy, self.coarse, self._canvas, self.large, self.command)

    def release(self):
        self._framebuffer.release()
        for resource in self.resources():
            resource.release()
