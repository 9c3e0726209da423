"""GLContext.clear zeroes float images both ways: by a compute pass (shaders/zero_image.comp,
what a GPU takes) and through a framebuffer (what llvmpipe takes). Real GL through llvmpipe."""
import numpy as np
import pytest


@pytest.mark.parametrize("by_compute", [True, False], ids=["compute pass", "framebuffer"])
@pytest.mark.parametrize("dtype, components", [("f4", 4), ("f2", 4), ("f4", 1)])
def test_clear_zeroes_every_texel(glc, by_compute, dtype, components, monkeypatch):
    size = (37, 21)  # not a multiple of the workgroup's 8 × 8
    texture = glc.gl.texture(size, components, data=np.ones(size[0] * size[1] * components, dtype=dtype).tobytes(),
                             dtype=dtype)
    monkeypatch.setattr(glc, "is_software", not by_compute)
    glc.clear(texture)
    assert not np.frombuffer(texture.read(), dtype=dtype).any()
    texture.release()
