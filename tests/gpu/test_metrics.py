"""Image error metrics (gpu/metrics.py) against hand-computed values and a brute-force SSIM."""
import math

import numpy as np
import pytest

from lpv_preview.gpu import metrics
from lpv_preview.gpu.errors import LPVError

# A 2x2 grey image pair used throughout; squared errors are 0.01, 0, 0, 0.04.
REFERENCE = np.array([[1.0, 0.5], [0.25, 0.0]])
TEST = np.array([[0.9, 0.5], [0.25, 0.2]])


def random_image(seed, shape=(16, 16, 3)):
    return np.random.default_rng(seed).uniform(0.0, 4.0, shape)  # HDR: values above 1


def assert_one_sentence(error):
    message = str(error.value)
    assert message.endswith(".") and ". " not in message and "\n" not in message, message


# ----------------------------------------------------------------------------- MSE / PSNR / relMSE

def test_mse_and_psnr_by_hand():
    # MSE = (0.01 + 0 + 0 + 0.04) / 4 = 0.0125; peak = max(reference) = 1;
    # PSNR = 10 log10(1 / 0.0125) = 10 log10(80) = 19.0309 dB.
    assert metrics.mse(TEST, REFERENCE) == pytest.approx(0.0125, rel=1e-14)
    assert metrics.psnr(TEST, REFERENCE) == pytest.approx(10 * math.log10(80), rel=1e-14)
    assert metrics.psnr(TEST, REFERENCE) == pytest.approx(19.0309, abs=1e-4)
    # An explicit peak of 2: 10 log10(4 / 0.0125) = 10 log10(320).
    assert metrics.psnr(TEST, REFERENCE, peak=2.0) == pytest.approx(10 * math.log10(320), rel=1e-14)


def test_relative_mse_by_hand():
    # (0.01 / (1 + 0.01) + 0 + 0 + 0.04 / (0 + 0.01)) / 4: the black reference pixel dominates.
    expected = (0.01 / 1.01 + 0.04 / 0.01) / 4
    assert metrics.relative_mse(TEST, REFERENCE) == pytest.approx(expected, rel=1e-14)
    # With epsilon = 1: (0.01 / 2 + 0.04 / 1) / 4.
    assert metrics.relative_mse(TEST, REFERENCE, epsilon=1.0) == pytest.approx((0.005 + 0.04) / 4, rel=1e-14)


def test_rgb_metrics_average_over_pixels_and_channels():
    reference = np.array([[[1.0, 2.0, 0.0], [0.5, 0.5, 0.5]]])      # (1, 2, 3)
    test = reference + np.array([[[0.1, 0.0, 0.0], [0.0, 0.0, -0.3]]])
    # MSE = (0.01 + 0.09) / 6; peak = 2 (max over all channels).
    assert metrics.mse(test, reference) == pytest.approx(0.1 / 6, rel=1e-12)
    assert metrics.psnr(test, reference) == pytest.approx(10 * math.log10(4 / (0.1 / 6)), rel=1e-12)
    # relMSE: per channel R: 0.01/1.01/2, G: 0, B: 0.09/0.26/2; averaged over the 3 channels.
    per_channel = [0.01 / 1.01 / 2, 0.0, 0.09 / (0.25 + 0.01) / 2]
    assert metrics.relative_mse(test, reference) == pytest.approx(np.mean(per_channel), rel=1e-12)


def test_identical_images():
    image = random_image(1, (12, 9, 3))
    assert metrics.mse(image, image.copy()) == 0.0
    assert metrics.psnr(image, image.copy()) == math.inf
    assert metrics.relative_mse(image, image.copy()) == 0.0
    assert metrics.ssim(image, image.copy()) == 1.0
    assert metrics.ssim(image[..., 0], image[..., 0].copy()) == 1.0
    mask = np.zeros((12, 9), bool)
    mask[3:7, 2:5] = True
    assert metrics.ssim(image, image.copy(), mask) == 1.0
    assert metrics.psnr(image, image.copy(), mask) == math.inf


def test_flip_is_zero_for_identical_images_and_grows_with_the_difference():
    image = random_image(2, (24, 24, 3))
    assert metrics.flip(image, image.copy())[0] == 0.0
    errors = [metrics.flip(image * scale, image)[0] for scale in (1.02, 1.2, 2.0)]
    assert 0.0 < errors[0] < errors[1] < errors[2] <= 1.0
    mean, error_map = metrics.flip(image * 1.2, image)
    assert error_map.shape == (24, 24) and mean == pytest.approx(float(error_map.mean()), rel=1e-6)
    mask = np.zeros((24, 24), bool)
    mask[:8] = True
    assert metrics.flip(image * 1.2, image, mask)[0] == pytest.approx(float(error_map[mask].mean()), rel=1e-6)


def test_image_errors_of_identical_images_are_perfect():
    image = random_image(3, (16, 16, 3))
    mean = float(image.mean())
    assert metrics.image_errors(image, image.copy()) == {"psnr": math.inf, "relative_mse": 0.0, "ssim": 1.0,
                                                         "flip": 0.0, "mse": 0.0, "mean": mean, "reference_mean": mean}


def test_image_errors_against_a_black_reference_are_absolute():
    black = np.zeros((8, 8, 3))
    errors = metrics.image_errors(black + 0.1, black)
    assert {name: errors[name] for name in metrics.RELATIVE_FIGURES} == dict.fromkeys(metrics.RELATIVE_FIGURES)
    assert errors["mse"] == pytest.approx(0.01) and errors["mean"] == pytest.approx(0.1)
    assert errors["reference_mean"] == 0.0


def test_flip_needs_rgb_images_and_a_lit_reference():
    with pytest.raises(LPVError, match="RGB") as grey:
        metrics.flip(REFERENCE, TEST)
    assert_one_sentence(grey)
    with pytest.raises(LPVError, match="black") as black:
        metrics.flip(random_image(4, (4, 4, 3)), np.zeros((4, 4, 3)))
    assert_one_sentence(black)


def test_psnr_of_black_reference():
    black = np.zeros((2, 2, 3))
    assert metrics.psnr(black, black) == math.inf          # identical wins
    assert metrics.psnr(black + 0.1, black) == -math.inf   # no peak: -inf, not a warning or nan
    assert metrics.psnr(black + 0.1, black, peak=1.0) == pytest.approx(20.0, rel=1e-12)  # 10 log10(1/0.01)


def test_masks():
    # Only the top row: MSE = (0.01 + 0) / 2 = 0.005, peak = 1 -> PSNR = 10 log10(200).
    mask = np.array([[True, True], [False, False]])
    assert metrics.mse(TEST, REFERENCE, mask) == pytest.approx(0.005, rel=1e-14)
    assert metrics.psnr(TEST, REFERENCE, mask) == pytest.approx(10 * math.log10(200), rel=1e-14)
    # Only the bottom row: the peak is 0.25 over the masked pixels; MSE = 0.04 / 2 = 0.02.
    bottom = ~mask
    assert metrics.psnr(TEST, REFERENCE, bottom) == pytest.approx(10 * math.log10(0.0625 / 0.02), rel=1e-14)
    assert metrics.relative_mse(TEST, REFERENCE, bottom) == pytest.approx(0.04 / 0.01 / 2, rel=1e-14)

    # (H, W) mask over an (H, W, 3) image equals the metric on the selected pixels.
    test, reference = random_image(2, (5, 6, 3)), random_image(3, (5, 6, 3))
    mask = np.random.default_rng(4).random((5, 6)) < 0.5
    assert metrics.mse(test, reference, mask) == pytest.approx(np.mean((test[mask] - reference[mask]) ** 2))
    assert metrics.psnr(test, reference, mask) == pytest.approx(metrics.psnr(test[mask], reference[mask]))
    assert metrics.relative_mse(test, reference, mask) == pytest.approx(
        metrics.relative_mse(test[mask], reference[mask]))

    # (N, C) texel sets with an (N,) mask.
    texels_t, texels_r = test.reshape(-1, 3), reference.reshape(-1, 3)
    flat = mask.reshape(-1)
    assert metrics.mse(texels_t, texels_r, flat) == pytest.approx(metrics.mse(test, reference, mask), rel=1e-14)

    # SSIM: the mask picks pixels of the SSIM map.
    full = metrics.ssim_map(metrics.luminance(test), metrics.luminance(reference),
                            metrics.luminance(reference)[mask].max())
    assert metrics.ssim(test, reference, mask) == pytest.approx(full[mask].mean(), rel=1e-14)


# ----------------------------------------------------------------------------- SSIM

def brute_force_ssim_map(x, y, dynamic_range, radius=5, sigma=1.5):
    """Windowed means, variances and covariance by explicit loops; window clipped to the image."""
    c1, c2 = (0.01 * dynamic_range) ** 2, (0.03 * dynamic_range) ** 2
    height, width = x.shape
    result = np.empty((height, width))
    for i in range(height):
        for j in range(width):
            weights, xs, ys = [], [], []
            for di in range(-radius, radius + 1):
                for dj in range(-radius, radius + 1):
                    if 0 <= i + di < height and 0 <= j + dj < width:
                        weights.append(math.exp(-(di * di + dj * dj) / (2 * sigma * sigma)))
                        xs.append(x[i + di, j + dj])
                        ys.append(y[i + di, j + dj])
            total = sum(weights)
            w = [v / total for v in weights]
            mu_x = sum(a * b for a, b in zip(w, xs))
            mu_y = sum(a * b for a, b in zip(w, ys))
            var_x = sum(a * (b - mu_x) ** 2 for a, b in zip(w, xs))
            var_y = sum(a * (b - mu_y) ** 2 for a, b in zip(w, ys))
            cov = sum(a * (b - mu_x) * (c - mu_y) for a, b, c in zip(w, xs, ys))
            result[i, j] = ((2 * mu_x * mu_y + c1) * (2 * cov + c2)) / (
                (mu_x ** 2 + mu_y ** 2 + c1) * (var_x + var_y + c2))
    return result


@pytest.mark.parametrize("shape", [(16, 16, 3), (7, 5, 3)])
def test_ssim_matches_brute_force(shape):
    test, reference = random_image(10, shape), random_image(11, shape)
    weights = np.array([0.2126, 0.7152, 0.0722])
    y_test, y_reference = test @ weights, reference @ weights
    expected_map = brute_force_ssim_map(y_test, y_reference, y_reference.max())
    assert np.max(np.abs(metrics.ssim_map(y_test, y_reference, y_reference.max()) - expected_map)) < 1e-9
    assert abs(metrics.ssim(test, reference) - expected_map.mean()) < 1e-9

    mask = np.random.default_rng(12).random(shape[:2]) < 0.4
    masked_map = brute_force_ssim_map(y_test, y_reference, y_reference[mask].max())
    assert abs(metrics.ssim(test, reference, mask) - masked_map[mask].mean()) < 1e-9


def test_ssim_decreases_with_noise():
    rows, cols = np.mgrid[0:32, 0:32] / 32.0
    base = np.stack([rows, cols, 0.5 + 0.5 * np.sin(6 * rows * cols)], axis=-1) * 3.0
    noise = np.random.default_rng(5).normal(size=base.shape)
    scores = [metrics.ssim(base + level * noise, base) for level in (0.01, 0.1, 0.5)]
    assert all(score < 1.0 for score in scores)
    assert scores[0] > scores[1] > scores[2]


def test_ssim_scale_invariance_of_hdr_convention():
    # L follows the reference, so scaling both images leaves SSIM unchanged.
    test, reference = random_image(6, (10, 10, 3)), random_image(7, (10, 10, 3))
    assert metrics.ssim(100 * test, 100 * reference) == pytest.approx(metrics.ssim(test, reference), rel=1e-10)


# ----------------------------------------------------------------------------- error and heat maps

def test_error_map_by_hand():
    reference = np.array([[1.0, 0.0]])
    test = np.array([[1.5, 0.1]])
    # 0.5 / (1 + 0.01) and 0.1 / (0 + 0.01).
    errors = metrics.error_map(test, reference)
    assert errors.dtype == np.float32 and errors.shape == (1, 2)
    np.testing.assert_allclose(errors, [[0.5 / 1.01, 10.0]], rtol=1e-6)

    reference_rgb = np.array([[[1.0, 2.0, 4.0]]])
    test_rgb = np.array([[[1.0, 3.0, 2.0]]])
    # Mean over channels of 0, 1 / 2.01, 2 / 4.01.
    np.testing.assert_allclose(metrics.error_map(test_rgb, reference_rgb), [[(1 / 2.01 + 2 / 4.01) / 3]], rtol=1e-6)
    assert metrics.error_map(test_rgb, reference_rgb).shape == (1, 1)


def test_heat_map():
    errors = np.array([[0.0, 0.5], [1.0, 3.0]], np.float32)
    rgb = metrics.heat_map(errors, vmax=1.0)
    assert rgb.dtype == np.float32 and rgb.shape == (2, 2, 3)
    assert rgb.min() >= 0.0 and rgb.max() <= 1.0
    np.testing.assert_allclose(rgb[0, 0], metrics.HEAT_RAMP[0], rtol=1e-6)
    np.testing.assert_allclose(rgb[1, 0], metrics.HEAT_RAMP[-1], rtol=1e-6)
    np.testing.assert_allclose(rgb[1, 1], metrics.HEAT_RAMP[-1], rtol=1e-6)   # clipped above vmax
    np.testing.assert_allclose(metrics.heat_map(errors)[1, 1], metrics.HEAT_RAMP[-1], rtol=1e-6)  # default vmax = max
    assert np.all(metrics.heat_map(np.zeros((3, 3))) == metrics.heat_map(np.zeros((3, 3)))[0, 0])

    # Perceptually ordered: the ramp's luminance rises strictly from 0 to vmax.
    ramp = metrics.heat_map(np.linspace(0.0, 1.0, 257)[None, :])[0]
    lightness = ramp.astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])
    assert np.all(np.diff(lightness) > 0)


# ----------------------------------------------------------------------------- errors

@pytest.mark.parametrize("call", [
    lambda: metrics.mse(np.zeros((2, 2)), np.zeros((2, 3))),
    lambda: metrics.psnr(np.zeros((2, 2, 3)), np.zeros((2, 2))),
    lambda: metrics.ssim(np.zeros((4, 4, 3)), np.ones((4, 5, 3))),
    lambda: metrics.error_map(np.zeros((2, 2, 3)), np.zeros((2, 2, 4))),
    lambda: metrics.mse(TEST, REFERENCE, np.zeros((2, 2), bool)),
    lambda: metrics.ssim(TEST, REFERENCE, np.zeros((2, 2), bool)),
    lambda: metrics.relative_mse(TEST, REFERENCE, np.ones((2, 3), bool)),
    lambda: metrics.mse(TEST, REFERENCE, np.ones((2, 2), int)),
    lambda: metrics.ssim(np.ones((4, 4, 3)), np.ones((4, 4, 3)), np.ones(4, bool)),
    lambda: metrics.mse(TEST, np.where(REFERENCE > 0.9, np.nan, REFERENCE)),
    lambda: metrics.psnr(np.full((2, 2), np.inf), REFERENCE),
    lambda: metrics.ssim(TEST, np.where(REFERENCE > 0.9, -np.inf, REFERENCE)),
    lambda: metrics.heat_map(np.array([[np.nan]])),
    lambda: metrics.mse(np.zeros((0, 3)), np.zeros((0, 3))),
    lambda: metrics.mse(np.zeros((1, 2, 2, 3)), np.zeros((1, 2, 2, 3))),
    lambda: metrics.ssim(np.zeros((4, 4)) + 0.1, np.zeros((4, 4))),
    lambda: metrics.psnr(TEST, REFERENCE, peak=0.0),
    lambda: metrics.relative_mse(TEST, REFERENCE, epsilon=0.0),
    lambda: metrics.heat_map(np.ones((2, 2)), vmax=-1.0),
    lambda: metrics.mse("abc", REFERENCE),
])
def test_errors_are_one_sentence(call):
    with pytest.raises(LPVError) as error:
        call()
    assert_one_sentence(error)


def test_metrics_module_never_imports_bpy():
    import inspect
    assert "bpy" not in inspect.getsource(metrics)
