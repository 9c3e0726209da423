"""Image error metrics between a test image and a reference (numpy only, float64 inside).

Inputs are linear-RGB HDR arrays of shape (H, W, 3), grey images (H, W), or flat sets of
texel values (N, C); test and reference have the same shape. `mask` is an optional boolean
array whose shape is the leading part of the data's shape ((H, W) for an (H, W, 3) image,
(N,) for an (N, C) set, or the whole shape); only the pixels/texels it selects count.
Shape mismatches, a non-boolean or empty mask and NaN/infinity anywhere in either array
raise LPVError. Scalar metrics return Python floats.

FLIP is computed by NVIDIA's `flip-evaluator` package (`flip`), HDR mode on the linear
images; `image_errors` gives every metric of a comparison in one dict.
"""
import math

import numpy as np

from .colour import LUMINANCE_WEIGHTS
from .errors import LPVError

SSIM_RADIUS = 5          # 11x11 window
SSIM_SIGMA = 1.5
SSIM_K1 = 0.01
SSIM_K2 = 0.03

# Matplotlib's inferno at 0, 1/8, ..., 1 (its table entries 0, 32, 64, 96, 128, 159, 191, 223, 255),
# sRGB-encoded display values; interpolated linearly, its lightness rises monotonically.
HEAT_RAMP = np.array([
    [0.001462, 0.000466, 0.013866],
    [0.129285, 0.047293, 0.290788],
    [0.341500, 0.062325, 0.429425],
    [0.540920, 0.134729, 0.415123],
    [0.735683, 0.215906, 0.330245],
    [0.890341, 0.347957, 0.198286],
    [0.977092, 0.550850, 0.039050],
    [0.976108, 0.789974, 0.196018],
    [0.988362, 0.998364, 0.644924],
])


# ----------------------------------------------------------------------------- validation

def _as_float(array, name):
    try:
        values = np.asarray(array, dtype=np.float64)
    except (TypeError, ValueError):
        raise LPVError(f"The {name} is not an array of numbers; pass a float image or texel array.") from None
    if values.size == 0:
        raise LPVError(f"The {name} is empty; pass an image or texel set with at least one value.")
    if not np.all(np.isfinite(values)):
        raise LPVError(f"The {name} contains NaN or infinite values; clamp or fix them before comparing.")
    return values


def _pair(test, reference):
    """Both arrays as validated float64 arrays of one shape, (N,) up to (H, W, C)."""
    test = _as_float(test, "test image")
    reference = _as_float(reference, "reference image")
    if test.shape != reference.shape:
        raise LPVError(f"The test image has shape {test.shape} but the reference has shape "
                       f"{reference.shape}; compare arrays of the same shape.")
    if not 1 <= test.ndim <= 3:
        raise LPVError(f"The images have shape {test.shape}; pass (H, W, 3) or (H, W) images or (N, C) texel sets.")
    return test, reference


def _as_mask(mask, shape):
    mask = np.asarray(mask)
    if mask.dtype != np.bool_:
        raise LPVError(f"The mask has dtype {mask.dtype}; pass a boolean mask.")
    if mask.ndim == 0 or mask.shape != tuple(shape[:mask.ndim]):
        raise LPVError(f"The mask has shape {mask.shape}, which does not match the images' shape {tuple(shape)}; "
                       f"pass a mask of the pixel shape.")
    if not mask.any():
        raise LPVError("The mask selects no pixels; select at least one pixel to compare.")
    return mask


def _selected(test, reference, mask):
    """Validated float64 (K, C) arrays of the selected pixels/texels (C = 1 without a channel axis)."""
    test, reference = _pair(test, reference)
    if mask is None:
        channels = test.shape[-1] if test.ndim >= 2 else 1
        return test.reshape(-1, channels), reference.reshape(-1, channels)
    mask = _as_mask(mask, test.shape)
    count = int(mask.sum())
    return test[mask].reshape(count, -1), reference[mask].reshape(count, -1)


# ----------------------------------------------------------------------------- scalar metrics

def mse(test, reference, mask=None):
    """Mean squared error over every selected pixel and channel: mean((test - reference)^2)."""
    t, r = _selected(test, reference, mask)
    return float(np.mean((t - r) ** 2))


def psnr(test, reference, mask=None, peak=None):
    """Peak signal-to-noise ratio in dB: 10 log10(peak^2 / MSE), MSE as in `mse`.

    `peak` defaults to the reference's maximum over the selected pixels and all channels
    (HDR images have no fixed white; the thesis compares LPV images this way). Identical
    images give +inf. With the default peak, a reference whose maximum is <= 0 (black)
    and a test that differs from it give -inf (the limit of log10(peak^2/MSE) as peak -> 0).
    An explicit `peak` must be a finite positive number.
    """
    t, r = _selected(test, reference, mask)
    if peak is None:
        peak = float(r.max())
    elif not (np.isfinite(peak) and peak > 0):
        raise LPVError(f"The PSNR peak is {peak}; pass a finite positive peak or leave it out.")
    error = float(np.mean((t - r) ** 2))
    if error == 0.0:
        return float("inf")
    if peak <= 0.0:
        return float("-inf")
    return float(10.0 * np.log10(peak * peak / error))


RELATIVE_EPSILON = 1e-2
"""The relative MSE's epsilon: squared radiance below which a reference pixel counts as that."""


def relative_mse(test, reference, mask=None, epsilon=RELATIVE_EPSILON):
    """Relative MSE of the rendering literature: mean of (test - ref)^2 / (ref^2 + epsilon).

    Averaged over the selected pixels per channel, then over the channels (the same as the
    mean over all selected values, as every channel has the same count). `epsilon` (in
    squared radiance units, default 1e-2) keeps near-black reference pixels from dominating;
    it must be finite and positive.
    """
    if not (np.isfinite(epsilon) and epsilon > 0):
        raise LPVError(f"The relative MSE epsilon is {epsilon}; pass a finite positive epsilon.")
    t, r = _selected(test, reference, mask)
    per_channel = np.mean((t - r) ** 2 / (r * r + epsilon), axis=0)
    return float(np.mean(per_channel))


# ----------------------------------------------------------------------------- SSIM

def _gaussian_taps(radius=SSIM_RADIUS, sigma=SSIM_SIGMA):
    offsets = np.arange(-radius, radius + 1, dtype=np.float64)
    taps = np.exp(-offsets ** 2 / (2.0 * sigma * sigma))
    return taps / taps.sum()


def _filter_axis(stack, axis, taps):
    """Correlate `stack` with the symmetric 1-D `taps` along `axis`, window clipped to the
    image and its weights renormalised to sum to 1 (so borders average existing pixels)."""
    radius = len(taps) // 2
    n = stack.shape[axis]
    pad = [(0, 0)] * stack.ndim
    pad[axis] = (radius, radius)
    padded = np.pad(stack, pad)
    ones = np.pad(np.ones(n), (radius, radius))
    total = np.zeros_like(stack)
    norm = np.zeros(n)
    for k, weight in enumerate(taps):
        total += weight * np.take(padded, np.arange(k, k + n), axis=axis)
        norm += weight * ones[k:k + n]
    shape = [1] * stack.ndim
    shape[axis] = n
    return total / norm.reshape(shape)


def gaussian_blur(stack):
    """Separable 11x11 Gaussian (sigma 1.5) over the last two axes, window clipped at borders."""
    taps = _gaussian_taps()
    return _filter_axis(_filter_axis(stack, stack.ndim - 2, taps), stack.ndim - 1, taps)


def luminance(image):
    """Rec. 709 luminance of an (H, W, 3) linear image; an (H, W) image is taken as luminance."""
    if image.ndim == 3 and image.shape[2] == 3:
        return image @ LUMINANCE_WEIGHTS
    if image.ndim == 2:
        return image
    raise LPVError(f"The images have shape {image.shape}; SSIM needs (H, W, 3) or (H, W) images.")


def ssim_map(test, reference, dynamic_range):
    """Per-pixel SSIM of two (H, W) luminance images (Wang et al. 2004)."""
    c1 = (SSIM_K1 * dynamic_range) ** 2
    c2 = (SSIM_K2 * dynamic_range) ** 2
    mu_x, mu_y, xx, yy, xy = gaussian_blur(np.stack([test, reference, test * test,
                                                     reference * reference, test * reference]))
    var_x = xx - mu_x * mu_x
    var_y = yy - mu_y * mu_y
    cov = xy - mu_x * mu_y
    return ((2.0 * mu_x * mu_y + c1) * (2.0 * cov + c2)) / ((mu_x * mu_x + mu_y * mu_y + c1) * (var_x + var_y + c2))


def ssim(test, reference, mask=None):
    """Mean structural similarity of the Rec. 709 luminances, in [-1, 1]; 1 for identical images.

    Gaussian window 11x11, sigma 1.5 (separable; at the image border the window is clipped
    to the image and renormalised), K1 = 0.01, K2 = 0.03, population (weighted) variances,
    dynamic range L = the reference's maximum luminance over the selected pixels (HDR has
    no fixed white). `mask` ((H, W)) selects the pixels of the SSIM map that are averaged;
    the windows themselves still see every pixel. A reference with no positive luminance
    over the mask has no dynamic range and raises LPVError.
    """
    test, reference = _pair(test, reference)
    y_test, y_reference = luminance(test), luminance(reference)
    if mask is not None:
        mask = _as_mask(mask, y_test.shape)
        if mask.shape != y_test.shape:
            raise LPVError(f"The mask has shape {mask.shape}; SSIM needs an (H, W) mask of the pixels.")
    dynamic_range = float(y_reference.max() if mask is None else y_reference[mask].max())
    if dynamic_range <= 0.0:
        raise LPVError("The reference is black where compared, so SSIM has no dynamic range; "
                       "compare against a lit reference.")
    values = ssim_map(y_test, y_reference, dynamic_range)
    return float(np.mean(values if mask is None else values[mask]))


# ----------------------------------------------------------------------------- error images

def error_map(test, reference, epsilon=1e-2):
    """Per-pixel relative error |test - ref| / (|ref| + epsilon), averaged over the channels.

    (H, W, C) images give an (H, W) float32 map, (H, W) images an (H, W) map; `epsilon`
    (radiance units, default 1e-2) keeps black reference pixels finite.
    """
    if not (np.isfinite(epsilon) and epsilon > 0):
        raise LPVError(f"The error-map epsilon is {epsilon}; pass a finite positive epsilon.")
    test, reference = _pair(test, reference)
    if test.ndim not in (2, 3):
        raise LPVError(f"The images have shape {test.shape}; an error map needs (H, W, 3) or (H, W) images.")
    relative = np.abs(test - reference) / (np.abs(reference) + epsilon)
    if relative.ndim == 3:
        relative = relative.mean(axis=2)
    return relative.astype(np.float32)


def heat_map(errors, vmax=None):
    """An (H, W) error map as an (H, W, 3) float32 sRGB display image in [0, 1] (inferno ramp).

    Errors are scaled by `vmax` (default: the map's maximum) and clipped to [0, 1]; 0 is
    near-black, 1 pale yellow. An all-zero map with the default vmax is all near-black.
    The values are display-encoded: write them to a PNG without tone mapping.
    """
    errors = _as_float(errors, "error map")
    if vmax is None:
        vmax = float(errors.max())
    elif not (np.isfinite(vmax) and vmax > 0):
        raise LPVError(f"The heat-map vmax is {vmax}; pass a finite positive vmax or leave it out.")
    scaled = np.clip(errors / vmax, 0.0, 1.0) if vmax > 0 else np.zeros_like(errors)
    positions = np.linspace(0.0, 1.0, len(HEAT_RAMP))
    rgb = np.stack([np.interp(scaled, positions, HEAT_RAMP[:, c]) for c in range(3)], axis=-1)
    return rgb.astype(np.float32)


# ----------------------------------------------------------------------------- FLIP

FLIP_PIXELS_PER_DEGREE = 67.0  # FLIP's default: a 0.7 m wide 4K monitor seen from 0.7 m


def flip(test, reference, mask=None):
    """Mean HDR-FLIP error (Andersson et al. 2021), in [0, 1]; 0 for identical images.

    Both images are linear RGB (H, W, 3), negative values clamped to 0 (FLIP takes
    non-negative radiance). HDR-FLIP tone-maps both with ACES at a range of exposures that
    it derives from the reference (its default start and stop exposures) and keeps each
    pixel's largest LDR-FLIP error; `FLIP_PIXELS_PER_DEGREE` sets the viewing distance.
    `mask` ((H, W)) selects the pixels of the error map that are averaged. Returns the
    mean and the (H, W) float32 error map.
    """
    import flip_evaluator
    test, reference = _pair(test, reference)
    if test.ndim != 3 or test.shape[2] != 3:
        raise LPVError(f"The images have shape {test.shape}; FLIP needs (H, W, 3) RGB images.")
    if mask is not None:
        mask = _as_mask(mask, test.shape[:2])
    if float(reference.max()) <= 0.0:
        raise LPVError("The reference is black, so HDR-FLIP has no exposure range; compare against a lit reference.")
    errors, _, _ = flip_evaluator.evaluate(
        np.ascontiguousarray(np.maximum(reference, 0.0), dtype=np.float32),
        np.ascontiguousarray(np.maximum(test, 0.0), dtype=np.float32), "HDR", inputsRGB=False,
        applyMagma=False, computeMeanError=False, parameters={"ppd": FLIP_PIXELS_PER_DEGREE})
    errors = np.asarray(errors, dtype=np.float32).reshape(test.shape[:2])
    return float(np.mean(errors if mask is None else errors[mask])), errors


RELATIVE_FIGURES = ("psnr", "relative_mse", "ssim", "flip")
"""The figures of `image_errors` measured against the reference's own scale."""


def image_errors(test, reference, mask=None):
    """Every figure of a comparison: the absolute ones, MSE and the mean of each image
    ("mean", "reference_mean"), and the relative ones, PSNR (peak: the reference's
    maximum), relative MSE, SSIM and mean HDR-FLIP of `test` against `reference`.

    A reference that is black where compared is an answer too, but it gives the relative
    figures no scale: they are None there, and the absolute ones say how far from black
    the test image is.
    """
    t, r = _selected(test, reference, mask)
    figures = {"mse": mse(test, reference, mask), "mean": float(np.mean(t)), "reference_mean": float(np.mean(r))}
    if not np.any(r > 0.0):
        return {**dict.fromkeys(RELATIVE_FIGURES), **figures}
    return {"psnr": psnr(test, reference, mask), "relative_mse": relative_mse(test, reference, mask),
            "ssim": ssim(test, reference, mask), "flip": flip(test, reference, mask)[0], **figures}


UNDEFINED = "—"
"""A figure that has no value, such as PSNR against a black reference."""


def figure_text(value, spec):
    """A figure as a table shows it: formatted by `spec` (like ".2f"), or a dash where it
    is undefined (None, or the infinite PSNR of identical images)."""
    return UNDEFINED if value is None or not math.isfinite(value) else format(value, spec)
