"""The corrected frame rebuilt from the samples a view gathered: the residual (Cycles
minus the preview) by normalised convolutions at growing scales that follow the G-buffer's
edges.

Two rules pick a scale per pixel and the frame takes the mean of their estimates: the
largest scale whose estimate agrees, within its noise, with every finer one (the
intersection of confidence intervals), and the scale of least risk (Stein's unbiased risk
estimate, averaged over a window). The intervals take each level's kernel as if its
samples were fresh, narrower at coarse scales than the cascade's true noise
(`CASCADE_VARIANCE`): that keeps finer scales where the preview errs in detail. The
intervals keep detail a small bias would cost but stop early on smooth surfaces; the risk
smooths where that pays but is noisy where samples are few; their mean errs less than
either (docs/method.md). Where samples are sparse each pixel takes the nearest ones,
blended where their regions meet, as the seed's blended Voronoi cells; where they are
dense, their average over the pixel alone: the resolution follows the samples. A pixel no
sample reached yet takes its neighbours' correction scaled to its own lighting where it is
darker, fading out with its distance from them.

Few samples make a correction that is mostly noise (a path tracer's first sample a pixel is
mostly darker than its mean and now and then far brighter): a correction is kept in the
share its noise leaves of it (positive-part James-Stein), so the preview shows where the
samples cannot yet tell it wrong.
"""
from dataclasses import dataclass

import numpy as np

from ..gpu.colour import LUMINANCE_WEIGHTS
from ..gpu.metrics import RELATIVE_EPSILON
from .guide import EdgeWeights

SCALES = 7
"""Levels of the reconstruction's à-trous filter beyond the pixel itself: steps 1 to 64 pixels."""
CONFIDENCE = 2.0
"""Half-width of a scale's confidence interval in standard deviations (the rule's Γ)."""
UNSAMPLED_ERROR = 0.25
"""Relative MSE assumed of the preview where no sample tells: what the first requests go for."""
NOISE_DOF = 4
"""Repeated requests a pixel's window needs before their spread alone measures the noise."""
RISK_RADIUS = 3
"""The risk of a scale is averaged over (2 r + 1)² pixels: a pixel's own is too noisy to choose by."""
OUTLIER = 4.0
"""A pixel whose own squared deviation from its window's mean passes this many times the window's
variance (a firefly) is given its own: its samples then spread over a larger scale."""
SHARE_LEVELS = 4
"""The share of a correction kept (_shrinkage) is averaged over the surface nearby by this many
levels of the reconstruction's filter (steps 1 to 8 pixels)."""
WIDE_RADIUS = 15
"""While a pixel's window has too few repeated requests to measure the noise, the spread of
the pixels' means over (2 r + 1)² pixels stands in where it is larger than over its window."""
AGREEING_DOF = 2
"""Repeated requests of its own (requests - 1) from which a pixel that stands out of its
window, but whose requests spread no more than OUTLIER times its window's, is detail they
agree on, not a firefly."""



@dataclass
class Reconstruction:
    """A corrected frame: the image, the correction added to the preview, each pixel's
    samples (gathered from every layer, aged) and estimated relative MSE, and the
    estimate's mean (`estimated_error`)."""

    image: np.ndarray
    correction: np.ndarray
    samples: np.ndarray
    error: np.ndarray
    estimated_error: float


def _unsampled_error(luminance):
    """The relative MSE assumed of pixels of this (non-negative) `luminance` no sample tells of."""
    return UNSAMPLED_ERROR * luminance * luminance / (luminance * luminance + RELATIVE_EPSILON)


def uncorrected(preview):
    """The Reconstruction of a view no sample reached: its preview."""
    error = _unsampled_error(np.maximum(preview @ LUMINANCE_WEIGHTS, 0.0)).astype(np.float32)
    height, width = preview.shape[:2]
    return Reconstruction(np.asarray(preview, np.float32), np.zeros((height, width, 3), np.float32),
                          np.zeros((height, width)), error, float(np.mean(error)))


def reconstruct(gathered, preview, guide):
    """The corrected preview from the Cycles samples `gathered` (Gathered), the preview and
    its Guide: the residual rebuilt scale by scale (module docstring); the preview itself
    where no sample is (a rebuild of nothing costs seconds at 1080p)."""
    total, samples = gathered.total, gathered.samples
    scale = guide.scale
    sampled = samples > 0
    if not sampled.any():  # no view's samples reach this one: nothing to rebuild
        return uncorrected(preview)
    mean = total / np.maximum(samples, 1e-30)[..., None]
    demodulated = preview / scale
    residual = np.where(sampled[..., None], mean - demodulated, 0.0)
    luminance = residual @ LUMINANCE_WEIGHTS
    variance, measured = _pooled_variance(luminance, samples, gathered.scatter, gathered.dof)
    numerator = residual * samples[..., None]
    # a pixel no sample reached takes the correction of those its scale reaches, scaled down
    # by its preview's lighting (demodulated) over theirs where it is darker: a lamp-lit
    # wall's missing light is not a shaded face's (theirs goes through the cascade as a
    # 4th channel, while any pixel has no sample)
    extrapolated = not sampled.all()
    if extrapolated:
        own_lighting = demodulated @ LUMINANCE_WEIGHTS
        numerator = np.concatenate([numerator, (samples * own_lighting)[..., None]], axis=-1)
    # the cascade in single precision: half the memory traffic of its filters, which are most of the time
    numerator, denominator, spread = (np.asarray(values, np.float32) for values in
                                      (numerator, samples, samples * variance))
    height, width = samples.shape
    # a pixel no sample reached takes no correction its preview's assumed error rules out
    preview_square = (preview @ LUMINANCE_WEIGHTS) ** 2 + RELATIVE_EPSILON
    prior = CONFIDENCE * np.sqrt(UNSAMPLED_ERROR * preview_square)
    prior /= scale @ LUMINANCE_WEIGHTS
    lower, upper = np.where(sampled, -np.inf, -prior), np.where(sampled, np.inf, prior)
    active = np.ones((height, width), dtype=bool)
    chosen, chosen_variance = np.zeros((height, width, 3)), np.full((height, width), np.nan)
    # Stein's unbiased risk of each scale, averaged over a window of sampled pixels weighed
    # as the relative MSE weighs them, and the scale of least risk with it
    risk_weight = np.where(sampled, (scale @ LUMINANCE_WEIGHTS) ** 2 / preview_square, 0.0)
    risk_norm = _box_sum(risk_weight, RISK_RADIUS)
    pixel_variance = variance / np.maximum(samples, 1e-30)
    best_risk = np.full((height, width), np.inf)
    risk_choice, risk = np.zeros((height, width, 3)), np.full((height, width), np.nan)
    risk_variance = np.zeros((height, width))
    own_weight = 1.0  # the cascade's weight of a pixel's own samples in its estimate
    edges = guide.edges
    for level in range(SCALES + 1):
        if level:
            numerator, denominator, spread = edges.filter(numerator, denominator, spread, 2 ** (level - 1))
            own_weight *= EdgeWeights.KERNEL[1] ** 2
        valid = denominator > 1e-12
        safe = np.where(valid, denominator, 1.0)
        estimate = numerator / safe[..., None]
        interval_variance = spread / (safe * safe)
        if extrapolated:
            dimming = np.where(sampled, 1.0, np.clip(own_lighting / np.maximum(estimate[..., 3], 1e-6), 0.0, 1.0))
            estimate = estimate[..., :3] * dimming[..., None]
            interval_variance = interval_variance * dimming * dimming  # the noise scales with the estimate
        estimate_variance = interval_variance * CASCADE_VARIANCE[level]
        centre = estimate @ LUMINANCE_WEIGHTS
        half = CONFIDENCE * np.sqrt(interval_variance)
        low, high = np.maximum(lower, centre - half), np.minimum(upper, centre + half)
        agrees = active & valid & (low <= high)
        active &= ~valid | agrees
        chosen[agrees], chosen_variance[agrees] = estimate[agrees], estimate_variance[agrees]
        lower, upper = np.where(agrees, low, lower), np.where(agrees, high, upper)
        # SURE of a normalised convolution: (estimate - own mean)² + 2 σ² d estimate / d own mean - σ²
        sure = np.where(sampled, (centre - luminance) ** 2 + 2 * variance * own_weight / safe - pixel_variance, 0.0)
        level_risk = np.where(risk_norm > 0, _box_sum(sure * risk_weight, RISK_RADIUS) / np.maximum(risk_norm, 1e-30),
                              estimate_variance)
        allowed = valid & (sampled | (np.abs(centre) <= prior))
        better = allowed & (level_risk < best_risk)
        best_risk = np.where(better, level_risk, best_risk)
        risk_choice[better], risk[better] = estimate[better], np.maximum(level_risk, estimate_variance)[better]
        risk_variance[better] = estimate_variance[better]
    risk_choice = np.where(np.isfinite(risk)[..., None], risk_choice, chosen)
    known = np.isfinite(chosen_variance)
    # the two rules' estimates averaged: no worse than their mean error, and either's
    # misjudged pixels halved
    blended = 0.5 * (chosen + risk_choice)
    # the mean's noise, as if the two estimates' were fully correlated (the most it can be)
    noise = 0.25 * (np.sqrt(np.nan_to_num(chosen_variance)) + np.sqrt(risk_variance)) ** 2
    # kept whole where repeated requests measured the noise; where one request's spread
    # judged it, in the share the noise leaves, averaged over the surface nearby: a pixel's
    # own follows its noise estimate, which a bright sample nearby raises, and would leave
    # the correction in patches
    kept_share = np.where(measured, 1.0, _shrinkage(blended @ LUMINANCE_WEIGHTS, noise))
    if not measured.all():
        kept_share = _along_surfaces(kept_share, edges)
    if extrapolated:  # what reaches a pixel without samples fades out toward the cascade's reach
        kept_share *= np.where(sampled, 1.0, _reach_fade(sampled))
    correction = blended * kept_share[..., None] * scale
    image = preview + correction
    weight = scale @ LUMINANCE_WEIGHTS
    reference = np.maximum(image @ LUMINANCE_WEIGHTS, 0.0)
    # the intervals' scale: its noise and a bias as large as its interval allows; the risk's: itself
    kept = 0.5 * (1 + CONFIDENCE ** 2) * np.nan_to_num(chosen_variance)
    kept += 0.5 * np.where(np.isfinite(risk), risk, (1 + CONFIDENCE ** 2) * np.nan_to_num(chosen_variance))
    error = np.where(known & sampled, kept * weight * weight / (reference * reference + RELATIVE_EPSILON),
                     _unsampled_error(reference))
    return Reconstruction(image.astype(np.float32), correction.astype(np.float32), samples, error.astype(np.float32),
                          float(np.mean(error)))


def _shrinkage(estimate, noise):
    """The share of a correction `estimate` (of variance `noise`) kept: the positive-part
    James-Stein factor 1 - Γ² noise / estimate² (Γ = CONFIDENCE, the intervals' own), so a
    correction within Γ standard deviations of nothing fades out and the preview shows
    where samples are too few to tell."""
    square, least = estimate * estimate, CONFIDENCE ** 2 * noise
    return np.where(square > least, 1.0 - least / np.maximum(square, 1e-30), 0.0)


def _along_surfaces(image, edges):
    """`image` averaged over the surface nearby: SHARE_LEVELS levels of the reconstruction's
    edge-stopping filter (EdgeWeights `edges`)."""
    values, ones = image[..., None], np.ones(image.shape, np.float32)
    for level in range(SHARE_LEVELS):
        values, total, _ = edges.filter(values, ones, ones, 2 ** level)
        values = values / total[..., None]
    return values[..., 0]


def _reach_fade(sampled):
    """Per pixel, 1 - its distance from the nearest sampled pixel over the cascade's reach
    (2^SCALES - 1 pixels each way), at least 0: what reaches a pixel without samples fades
    out toward where it no longer reaches, instead of stopping there in a seam."""
    reach = 2 ** SCALES - 1
    return np.clip(1.0 - _distance_to(sampled, reach) / reach, 0.0, 1.0)


def _distance_to(marked, cap):
    """Per pixel, the distance (the larger of its rows and columns) to the nearest `marked`
    pixel, at most `cap`: a chamfer pass down the rows and one up, each row swept both ways
    at once."""
    width = marked.shape[1]
    column = np.arange(width, dtype=np.float64)
    distance = np.where(marked, 0.0, float(cap))
    for rows in (range(len(marked)), range(len(marked) - 1, -1, -1)):
        previous = None
        for y in rows:
            row = distance[y]
            if previous is not None:  # the row before and its diagonal neighbours, a step away
                beside = previous.copy()
                beside[1:] = np.minimum(beside[1:], previous[:-1])
                beside[:-1] = np.minimum(beside[:-1], previous[1:])
                row = np.minimum(row, beside + 1.0)
            row = np.minimum(np.minimum.accumulate(row - column) + column,
                             np.minimum.accumulate((row + column)[::-1])[::-1] - column)
            distance[y] = previous = row
    return np.minimum(distance, cap)


def _cascade_variance(levels):
    """Per level, the variance of the cascaded à-trous kernel's sum over that of the
    levels' own kernels multiplied (what `spread` carries): the levels share samples, so
    the variance falls slower than their product says. Exact for even weights (a plane
    sampled alike); 2D, each axis alike. The estimated error takes it; the confidence
    intervals do not (module docstring)."""
    kernel, product, factors = np.ones(1), 1.0, [1.0]
    for level in range(levels):
        step = 2 ** level
        taps = np.zeros(2 * step + 1)
        taps[0], taps[step], taps[-1] = EdgeWeights.KERNEL
        kernel = np.convolve(kernel, taps)
        product *= np.sum(taps * taps)
        factors.append(float(np.sum(kernel * kernel) / product) ** 2)
    return tuple(factors)


def _box_sum(image, radius):
    """Sums over (2 radius + 1)² windows, clipped at the borders."""
    padded = np.pad(image, radius)
    summed = padded.cumsum(0).cumsum(1)
    summed = np.pad(summed, ((1, 0), (1, 0)))
    side = 2 * radius + 1
    return summed[side:, side:] - summed[:-side, side:] - summed[side:, :-side] + summed[:-side, :-side]


def _pooled_variance(luminance, samples, scatter, dof, radius=2):
    """A sample's variance at each pixel, pooled over its window: from the spread of the
    requests' means about their pixels' own means where the window holds at least
    NOISE_DOF repeated requests (noise alone), a pixel whose own requests spread more, or
    that has fewer than NOISE_DOF repeated requests of its own and stands out of its window
    more than OUTLIER times its spread (a firefly among them), given its own unless its
    AGREEING_DOF or more repeated requests agree (detail); else, while one request a pixel is
    all there is, from the spread of the pixels' means about the window's (the residual's
    own variation counts too: conservative), a pixel far off it (a firefly) given its own;
    and where the noise is measured (the first case)."""
    repeated = _box_sum(dof, radius)
    window_spread = np.maximum(_box_sum(scatter, radius), 0.0) / np.maximum(repeated, 1.0)
    own_spread = scatter / np.maximum(dof, 1.0)
    measured = np.maximum(window_spread, own_spread)  # a firefly's requests spread it
    pooled, window_mean = _spatial_spread(luminance, samples, radius)
    # a window of a few pixels may hold none of the rare bright samples that a path
    # tracer's first sample a pixel scatters (their median lies far below their mean): the
    # spread over a wide window stands in where it is larger
    measured_noise = repeated >= NOISE_DOF
    if not measured_noise.all():
        pooled = np.fmax(pooled, _spatial_spread(luminance, samples, WIDE_RADIUS)[0])
    fallback = np.nanmax(pooled) if np.any(np.isfinite(pooled)) else 1.0
    pooled = np.where(np.isfinite(pooled), pooled, fallback)
    own = samples * (luminance - window_mean) ** 2
    spatial = np.where(own > OUTLIER * pooled, own, pooled)
    # a firefly in one of a pixel's few requests hardly spreads their means (the larger
    # request holds it and the mean): the pixel is judged against its window's then too,
    # but a detail every request shows (a window's edge, a lamp's speck) spreads them no
    # more than noise does
    firefly = (dof < NOISE_DOF) & (own > OUTLIER * np.maximum(pooled, measured))
    firefly &= (dof < AGREEING_DOF) | (own_spread > OUTLIER * window_spread)
    return np.where(measured_noise, np.where(firefly, own, measured), spatial), measured_noise


def _spatial_spread(luminance, samples, radius):
    """A sample's variance from the spread of the pixels' means about their window's
    ((2 radius + 1)² pixels; NaN where it holds fewer than two sampled pixels), and the
    window's mean."""
    weights = _box_sum(samples, radius)
    first = _box_sum(samples * luminance, radius)
    second = _box_sum(samples * luminance * luminance, radius)
    count = _box_sum((samples > 0).astype(np.float64), radius)
    spread = second - first * first / np.maximum(weights, 1e-30)
    pooled = np.where(count > 1, np.maximum(spread, 0.0) / np.maximum(count - 1, 1.0), np.nan)
    return pooled, first / np.maximum(weights, 1e-30)


CASCADE_VARIANCE = _cascade_variance(SCALES)
