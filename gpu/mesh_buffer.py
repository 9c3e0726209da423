"""The scene's triangles on the GPU, shared by every raster pass (RSM faces, G-buffer)."""
import numpy as np


class MeshBuffer:
    """One interleaved vertex buffer (position, normal, albedo) and its vertex arrays."""

    def __init__(self, glc, scene):
        count = scene.triangle_count
        albedo = np.repeat(scene.albedo[:, None, :], 3, axis=1)
        interleaved = np.concatenate([scene.triangles, scene.normals, albedo], axis=2).astype(np.float32)
        self.glc = glc
        self.vertex_count = count * 3
        self.buffer = glc.gl.buffer(interleaved.tobytes())
        self._arrays = {}

    def vertex_array(self, program):
        if program not in self._arrays:
            self._arrays[program] = self.glc.gl.vertex_array(
                program, [(self.buffer, "3f 3f 3f", "in_position", "in_normal", "in_albedo")])
        return self._arrays[program]

    def release(self):
        for array in self._arrays.values():
            array.release()
        self.buffer.release()
