"""SH math of the LPV (METHOD §7) against float64 numpy references, on the CPU and in GLSL."""
import math

import numpy as np
import pytest

from lpv_preview.gpu import lpv

from ..glsl import evaluate


def sphere_quadrature(n_theta=400, n_phi=800):
    """Gauss-Legendre in cos(theta) times a uniform rule in phi: directions and weights."""
    x, w = np.polynomial.legendre.leggauss(n_theta)
    phi = (np.arange(n_phi) + 0.5) * 2 * math.pi / n_phi
    cos_t, ph = np.meshgrid(x, phi, indexing="ij")
    sin_t = np.sqrt(1 - cos_t ** 2)
    dirs = np.stack([sin_t * np.cos(ph), sin_t * np.sin(ph), cos_t], -1).reshape(-1, 3)
    weights = np.repeat(w, n_phi) * (2 * math.pi / n_phi)
    return dirs, weights


def random_directions(count, seed=3):
    d = np.random.default_rng(seed).normal(size=(count, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def test_constants_are_the_exact_values():
    assert lpv.SH_C0 == pytest.approx(0.282094792, abs=1e-9)
    assert lpv.SH_C1 == pytest.approx(0.488602512, abs=1e-9)
    assert lpv.LOBE_C0 == pytest.approx(math.sqrt(math.pi) / 2, abs=1e-12)
    assert lpv.LOBE_C0 != pytest.approx(math.sqrt(math.pi) / 3, rel=1e-3)  # the shipped mistake
    assert lpv.LOBE_C1 == pytest.approx(math.sqrt(math.pi / 3), abs=1e-12)


def test_basis_is_orthonormal():
    dirs, weights = sphere_quadrature()
    y = lpv.sh_basis(dirs)
    gram = (y * weights[:, None]).T @ y
    np.testing.assert_allclose(gram, np.eye(4), atol=1e-9)


def test_cos_lobe_is_the_projection_of_the_clamped_cosine():
    dirs, weights = sphere_quadrature()
    for n in random_directions(5):
        clamped = np.maximum(0.0, dirs @ n)
        projection = (lpv.sh_basis(dirs) * (clamped * weights)[:, None]).sum(axis=0)
        np.testing.assert_allclose(projection, lpv.cos_lobe(n), atol=1e-6)
        assert (clamped * weights).sum() == pytest.approx(math.pi, rel=1e-6)


def test_cos_lobe_convolution_gives_the_irradiance_of_sh_radiance():
    """E(n) = integral of L(w) max(0, n.w) equals c . cosLobe(n) for radiance L = c . Y."""
    dirs, weights = sphere_quadrature()
    rng = np.random.default_rng(5)
    for n in random_directions(4, seed=9):
        c = rng.normal(size=4)
        radiance = lpv.sh_basis(dirs) @ c
        irradiance = (radiance * np.maximum(0.0, dirs @ n) * weights).sum()
        assert c @ lpv.cos_lobe(n) == pytest.approx(irradiance, abs=1e-6)


def test_face_solid_angles():
    # Far face: a unit square seen from 1.5 cells away; far + 4 sides = 2 pi / 3 (1/6 of the sphere).
    assert lpv.FAR_FACE_SOLID_ANGLE == pytest.approx(4 * math.asin(1 / 10), abs=1e-10)
    assert lpv.FAR_FACE_SOLID_ANGLE + 4 * lpv.SIDE_FACE_SOLID_ANGLE == pytest.approx(2 * math.pi / 3, abs=1e-9)
    assert lpv.SIDE_FACE_SOLID_ANGLE != pytest.approx(0.4234413544, abs=1e-9)  # the copied typo


def test_glsl_basis_and_lobe_match_numpy(glc):
    dirs = random_directions(256, seed=11)
    basis, lobe = evaluate(glc, "common.glsl", ["sh_basis(x.xyz)", "cos_lobe(x.xyz)"], dirs)
    error_basis = np.abs(basis - lpv.sh_basis(dirs)).max()
    error_lobe = np.abs(lobe - lpv.cos_lobe(dirs)).max()
    print(f"GLSL vs float64: basis {error_basis:.2e}, lobe {error_lobe:.2e}")
    assert error_basis < 1e-6 and error_lobe < 1e-6
