"""gpu/occupancy.py: the voxels the lights' triangles pass through."""
import numpy as np

from lpv_preview.bench.synthetic import room_scene
from lpv_preview.gpu import context
from lpv_preview.gpu.grids import fit_grid
from lpv_preview.gpu.mesh_buffer import MeshBuffer
from lpv_preview.gpu.occupancy import Occupancy


def test_the_occupancy_reaches_every_triangle_of_a_scene_larger_than_one_dispatch(glc, monkeypatch):
    # GL promises 65,535 workgroups a dispatch: 4,194,240 triangles in rows of 64. Rows
    # of 640 triangles here split the room's 19,200 into 30 dispatches, and the voxels
    # are the same.
    scene = room_scene(40)
    mesh = MeshBuffer(glc, scene)
    voxels = []
    for row in (context.ROW_INVOCATIONS, 640):
        monkeypatch.setattr(context, "ROW_INVOCATIONS", row)
        occupancy = Occupancy(glc, [fit_grid(scene.bounds(), 16)])
        occupancy.voxelise(mesh)
        voxels.append(np.frombuffer(occupancy.occupancy.read(), dtype=np.uint8).copy())
        occupancy.release()
    assert voxels[0].any()
    np.testing.assert_array_equal(voxels[1], voxels[0])
    mesh.release()


def test_a_floor_under_a_ceiling_is_voxelised_whole_at_fine_grids(glc):
    """Both project onto the same tiles of the voxelisation's canvas: where the ceiling,
    drawn later, covered a tile whole, llvmpipe dropped the floor's voxels there, and light
    leaked through the floor's holes at grids of 36 cells and more."""
    scene = room_scene(1)
    mesh = MeshBuffer(glc, scene)
    for cells in (16, 48):
        grid = fit_grid(scene.bounds(), cells)
        occupancy = Occupancy(glc, [grid], 6)
        occupancy.voxelise(mesh)
        n = occupancy.voxels
        voxels = np.frombuffer(occupancy.occupancy.read(), dtype=np.uint8).reshape(-1, n, n)[:n]
        voxel = grid.cell_size / 6
        floor = voxels[int(np.floor(-grid.origin[2] / voxel))]  # the layer z = 0 lies in
        inside = [slice(int(np.ceil((-2 - o) / voxel)), int(np.floor((2 - o) / voxel))) for o in grid.origin[1::-1]]
        assert floor[tuple(inside)].all(), (cells, float(floor[tuple(inside)].mean()))
        occupancy.release()
    mesh.release()
