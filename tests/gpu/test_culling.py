"""A view draws the clusters of triangles its frustum may see (gpu/mesh_buffer.py,
shaders/frustum_cull.comp): fewer triangles, the same picture."""
import numpy as np

from lpv_preview.gpu.mesh_buffer import CULL_COMMAND_BYTES, MeshBuffer
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import Settings

from ..synthetic_scenes import room_scene


def test_a_view_skips_what_lies_outside_its_frustum_and_draws_the_same_picture(glc, monkeypatch):
    """The camera stands by one wall of a room of 6,912 triangles (27 clusters) and looks
    away from it: the clusters of that wall are not drawn, and every pass (the point
    light's six cube faces, the G-buffer) gives the frame that drawing every triangle gives."""
    scene = room_scene(24)
    settings = Settings(width=96, height=72, method="cm")
    pipeline = Pipeline(settings, glc)
    try:
        culled = pipeline.render(scene).passes["combined"]
        mesh = pipeline._mesh.value  # the frame's mesh: which clusters its camera drew
        _, commands, clusters = mesh._clusters(mesh.camera_triangles)
        slot = mesh._cull_slot[mesh.camera_triangles]
        drawn = np.frombuffer(commands.read(), np.uint32).reshape(-1, CULL_COMMAND_BYTES // 4)
        instances = drawn[slot * clusters:(slot + 1) * clusters, 1]
        assert 0 < instances.sum() < clusters - 3  # the wall behind is one side's 4.5 clusters
    finally:
        pipeline.release()
    draw = MeshBuffer.draw
    monkeypatch.setattr(MeshBuffer, "draw", lambda self, program, mode, triangles, view_projection=None:
                        draw(self, program, mode, triangles))
    pipeline = Pipeline(settings, glc)
    try:
        whole = pipeline.render(scene).passes["combined"]
    finally:
        pipeline.release()
    np.testing.assert_array_equal(culled, whole)
