"""The paraboloid projection of METHOD §3 in float64 numpy: the reference the GLSL in
shaders/paraboloid.glsl is tested against, and what CPU-side checks use."""
import numpy as np


def project(p):
    """Map coordinates (s, t) of hemisphere-space points p (..., 3), +z the axis (eq. 3)."""
    p = np.asarray(p, dtype=np.float64)
    length = np.linalg.norm(p, axis=-1, keepdims=True)
    return p[..., :2] / np.maximum(length + p[..., 2:3], 1e-7 * length + 1e-30)


def direction(st):
    """Unit direction of map coordinates (s, t): (2s, 2t, 1 - s² - t²) / (1 + s² + t²)."""
    st = np.asarray(st, dtype=np.float64)
    r2 = np.sum(st * st, axis=-1, keepdims=True)
    return np.concatenate([2 * st, 1 - r2], axis=-1) / (1 + r2)


def texel_solid_angle(st, resolution):
    """Solid angle of a texel at (s, t) of a map with `resolution` texels across [-1, 1]."""
    r2 = np.sum(np.asarray(st, dtype=np.float64) ** 2, axis=-1)
    return 4.0 * (2.0 / resolution) ** 2 / (1 + r2) ** 2
