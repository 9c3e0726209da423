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
