"""A scene's camera G-buffer drawn by itself, for the tests that check what it holds."""
from lpv_preview.gpu.mesh_buffer import MeshBuffer
from lpv_preview.gpu.shade import FrameTargets, read_gbuffer_record, render_gbuffer


def drawn_gbuffer(glc, scene, size):
    """The GBufferRecord of a sanitized scene's camera at `size` (width, height)."""
    mesh, targets = MeshBuffer(glc, scene), FrameTargets(glc.gl, *size)
    try:
        render_gbuffer(glc, mesh, scene.camera, targets)
        return read_gbuffer_record(glc, targets, scene.camera)
    finally:
        mesh.release()
        targets.release()
