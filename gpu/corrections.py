"""Corrective texturing toward Cycles (issue 18, seed 001): Cycles samples of the view
correct the preview, and the corrections outlive a camera move.

The corrections are projective layers, as the seed's corrective textures are projected
from the viewpoint: one layer for every camera position that got samples, holding per
pixel the surface it saw (position, normal), its preview and the Cycles samples received
there, divided by the preview's albedo (lighting varies less than texture). A frame
looks every other layer up from its own pixels (`_lookup`: the same surface, within
footprints along the normal, normals alike, or background for background) and carries
over the samples' difference from that layer's preview; older layers weigh less (aging).

The frame's residual (Cycles minus its own preview) is then rebuilt over the image by
normalised convolutions at growing scales that follow the G-buffer's edges. Two rules pick
a scale per pixel and the frame takes the mean of their estimates: the largest scale whose
estimate agrees, within its noise, with every finer one (the intersection of confidence
intervals), and the scale of least risk (Stein's unbiased risk estimate, averaged over a
window). The intervals take each level's kernel as if its samples were fresh, narrower at
coarse scales than the cascade's true noise (`CASCADE_VARIANCE`): that keeps finer scales
where the preview errs in detail. The intervals keep detail a small bias would cost but
stop early on smooth surfaces; the risk smooths where that pays but is noisy where samples
are few; their mean errs less than either (docs/method.md). Where samples are sparse each
pixel takes the nearest ones, blended where their regions meet, as the seed's blended
Voronoi cells; where they are dense, their average over the pixel alone: the resolution
follows the samples. A pixel no sample reached yet takes its neighbours' correction scaled
to its own lighting where it is darker.
"""
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .colour import LUMINANCE_WEIGHTS
from .errors import LPVError
from .metrics import RELATIVE_EPSILON

ALBEDO_FLOOR = 0.05
"""Added to the albedo the samples are divided by and the corrections multiplied by: keeps
black surfaces, emitters and the background finite."""
SCALES = 7
"""Levels of the reconstruction's à-trous filter beyond the pixel itself: steps 1 to 64 pixels."""
CONFIDENCE = 2.0
"""Half-width of a scale's confidence interval in standard deviations (the rule's Γ)."""
NORMAL_POWER = 16
"""Sharpness of the normals' edge: a neighbour counts as (n·n')^NORMAL_POWER (a power of two)."""
PLANE_FOOTPRINTS = 1.0
"""A neighbour off the pixel's plane by this many pixel footprints times the step counts e^-1."""
SAME_SURFACE_NORMAL = 0.9
SAME_SURFACE_FOOTPRINTS = 2.0
"""A layer's pixel is the frame's surface when their normals' cosine is above
SAME_SURFACE_NORMAL and it lies within this many footprints of the frame's plane."""
LAYER_AGING = 0.5
"""Weight a layer keeps each time another view gets its first samples."""
MAX_LAYERS = 8
"""Layers kept (the oldest go), and views remembered."""
UNSAMPLED_ERROR = 0.25
"""Relative MSE assumed of the preview where no sample tells: what the first requests go for."""
NOISE_DOF = 4
"""Repeated requests a pixel's window needs before their spread alone measures the noise."""
RISK_RADIUS = 3
"""The risk of a scale is averaged over (2 r + 1)² pixels: a pixel's own is too noisy to choose by."""
OUTLIER = 4.0
"""A pixel whose own squared deviation from its window's mean passes this many times the window's
variance (a firefly) is given its own: its samples then spread over a larger scale."""
AGREEING_DOF = 2
"""Repeated requests of its own (requests - 1) from which a pixel that stands out of its
window, but whose requests spread no more than OUTLIER times its window's, is detail they
agree on, not a firefly."""


@dataclass
class Guide:
    """What the preview's G-buffer says of every pixel, (height, width, ...) top row first:
    the surface's position (where `seen`; elsewhere the ray's direction) in the scene's local
    frame, its normal and albedo, and a pixel's width there (`footprint`)."""

    position: np.ndarray
    normal: np.ndarray
    albedo: np.ndarray
    seen: np.ndarray
    footprint: np.ndarray

    @property
    def size(self):
        return self.seen.shape[1], self.seen.shape[0]

    @cached_property
    def scale(self):
        """What a radiance seen here is divided by to be demodulated, and a correction
        multiplied by: the albedo, ALBEDO_FLOOR added."""
        return self.albedo.astype(np.float64) + ALBEDO_FLOOR

    @cached_property
    def edges(self):
        """The à-trous filter's edge weights, made on the first reconstruction of this view."""
        return _Edges(self)


class Layer:
    """The Cycles samples received at one rest of the camera: per pixel their sum
    (demodulated), count, and the spread of the requests' means (luminance), from which
    their noise is known without the image's own variation."""

    def __init__(self, camera, guide, preview):
        self.camera, self.guide = camera, guide
        self.version = 0  # counts what changes the samples or the preview: what views carry over follows it
        self.set_preview(preview)
        height, width = guide.seen.shape
        self.sum = np.zeros((height, width, 3))  # samples × demodulated radiance
        self.samples = np.zeros((height, width))
        self.squares = np.zeros((height, width))  # Σ a request's samples × its mean's luminance²
        self.requests = np.zeros((height, width))
        self.weight = 1.0

    def set_preview(self, preview):
        """The preview the samples differ from (demodulated, as they are)."""
        self.preview = preview / self.guide.scale
        self.version += 1

    def add(self, region, combined, samples):
        x0, y0, x1, y1 = region
        self.version += 1
        finite = np.all(np.isfinite(combined), axis=-1)
        demodulated = np.where(finite[..., None], combined, 0.0) / self.guide.scale[y0:y1, x0:x1]
        self.sum[y0:y1, x0:x1] += samples * demodulated
        self.samples[y0:y1, x0:x1] += samples * finite
        self.squares[y0:y1, x0:x1] += samples * (demodulated @ LUMINANCE_WEIGHTS) ** 2
        self.requests[y0:y1, x0:x1] += finite

    def scatter(self):
        """Per pixel Σ samples × (a request's mean - the pixel's mean)² (luminance), and its
        degrees of freedom (requests - 1): (requests - 1) times a sample's variance, on average."""
        mean = (self.sum @ LUMINANCE_WEIGHTS) / np.maximum(self.samples, 1e-30)
        return np.maximum(self.squares - self.samples * mean * mean, 0.0), np.maximum(self.requests - 1, 0.0)


@dataclass
class Gathered:
    """Samples as one view sees them, per pixel: `total` (demodulated, aged), `samples`
    (aged), and the requests' `scatter` with its degrees of freedom `dof` (Layer.scatter)."""

    total: np.ndarray
    samples: np.ndarray
    scatter: np.ndarray
    dof: np.ndarray

    @staticmethod
    def empty(height, width):
        return Gathered(np.zeros((height, width, 3)), *(np.zeros((height, width)) for _ in range(3)))


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


class Corrections:
    """The views of one scene shown lately, and the layers of those that got samples,
    newest last."""

    def __init__(self):
        self.views = {}  # key -> (gpu Camera, Guide, preview)
        self.layers = {}
        self.settings = None  # the previews' settings
        # (layer key, view key) -> (the view's Guide, its _lookup of the layer, the layer's
        # version, what the view carries over of it then)
        self.carried = {}

    def view(self, key, camera, guide, preview, settings=None):
        """The view `key` (its gpu Camera, Guide and preview) is shown: remembered; its
        layer is made when its first samples come. Previews of other `settings` than the
        last view's leave the other layers out: what they carry over is their samples'
        difference from previews of the old settings (the view's own samples stay: Cycles'
        do not depend on the preview)."""
        if settings != self.settings:
            self.settings, self.views = settings, {}
            self.layers = {layer_key: layer for layer_key, layer in self.layers.items() if layer_key == key}
        self.views.pop(key, None)
        self.views[key] = (camera, guide, preview)
        if key in self.layers:  # back at a view: its samples count fully again, against its preview now
            layer = self.layers[key]
            layer.weight = 1.0
            layer.set_preview(preview)
        while len(self.views) > MAX_LAYERS:
            self.views.pop(next(iter(self.views)))

    def add(self, key, region, combined, samples):
        """Samples of `region` (x0, y0, x1, y1) of the view `key`: `combined` the Cycles
        radiance there ((y1 - y0, x1 - x0, 3); pixels not finite are left out), `samples`
        a pixel. A view's first samples make its layer, and the others age. False when
        the view was forgotten meanwhile."""
        x0, y0, x1, y1 = region
        if combined.shape != (y1 - y0, x1 - x0, 3):
            raise LPVError(f"Cycles samples of region {region} came as {combined.shape[1]} x {combined.shape[0]} "
                           f"pixels; the worker rendered another image than asked.")
        layer = self.layers.get(key)
        if layer is None:
            if key not in self.views:
                return False
            for older in self.layers.values():
                older.weight *= LAYER_AGING
            while len(self.layers) >= MAX_LAYERS:
                del self.layers[next(iter(self.layers))]
            layer = self.layers[key] = Layer(*self.views[key])
        layer.add(region, combined, samples)
        return True

    def gathered(self, key):
        """Every layer's samples as the view `key` sees them (Gathered)."""
        _, guide, preview = self.views[key]
        gathered = Gathered.empty(*guide.seen.shape)
        demodulated = (preview / guide.scale).reshape(-1, 3)
        for layer_key, layer in self.layers.items():
            if layer_key == key:
                scatter, dof = layer.scatter()
                gathered.total += layer.sum * layer.weight
                gathered.samples += layer.samples * layer.weight
                gathered.scatter += scatter
                gathered.dof += dof
                continue
            # the layer's residual carried over, added to this view's own preview
            residual, samples, scatter, dof = self._carried(layer_key, key)
            gathered.total += (residual + samples[:, None] * demodulated).reshape(gathered.total.shape) * layer.weight
            gathered.samples += samples.reshape(gathered.samples.shape) * layer.weight
            gathered.scatter += scatter.reshape(gathered.scatter.shape)
            gathered.dof += dof.reshape(gathered.dof.shape)
        return gathered

    def _carried(self, layer_key, key):
        """What the view `key` carries over of the layer `layer_key` (_project), made again
        only when the layer changed (a late result, its view shown again) or the view's
        guide did: a view rests many times while samples come. The lookup (_lookup)
        depends on the guide alone."""
        layer, guide = self.layers[layer_key], self.views[key][1]
        for pair in [pair for pair in self.carried if pair[0] not in self.layers or pair[1] not in self.views]:
            del self.carried[pair]
        made = self.carried.get((layer_key, key))
        if made is None or made[0] is not guide:
            made = (guide, _lookup(layer, guide), None, None)
        if made[2] != layer.version:
            made = self.carried[layer_key, key] = (guide, made[1], layer.version, _project(layer, made[1]))
        return made[3]

    def reconstruct(self, key):
        """The view `key`'s preview, corrected."""
        _, guide, preview = self.views[key]
        return reconstruct(self.gathered(key), preview, guide)


def _unsampled_error(luminance):
    """The relative MSE assumed of pixels of this (non-negative) `luminance` no sample tells of."""
    return UNSAMPLED_ERROR * luminance * luminance / (luminance * luminance + RELATIVE_EPSILON)


def uncorrected(preview):
    """The Reconstruction of a view no sample reached: its preview."""
    error = _unsampled_error(np.maximum(preview @ LUMINANCE_WEIGHTS, 0.0)).astype(np.float32)
    height, width = preview.shape[:2]
    return Reconstruction(np.asarray(preview, np.float32), np.zeros((height, width, 3), np.float32),
                          np.zeros((height, width)), error, float(np.mean(error)))


def _lookup(layer, target):
    """Where each pixel of the Guide `target` finds `layer`'s samples: its point projected
    into the layer's view, the four pixels around it weighed bilinearly where they saw the
    same surface (within SAME_SURFACE_FOOTPRINTS along the normal, normals alike) or, for
    background, background; [(source pixel, weight)] for the four, flat. Looking up rather
    than splatting leaves no holes and keeps a sample's surface point within a fraction of
    a pixel. It depends on the two guides and the layer's camera alone: made once a view
    (Corrections.gathered)."""
    source, camera = layer.guide, layer.camera
    height, width = source.seen.shape
    points = target.position.reshape(-1, 3).astype(np.float64)
    seen = target.seen.reshape(-1)
    normal = target.normal.reshape(-1, 3).astype(np.float64)
    footprint = target.footprint.reshape(-1)
    clip = np.concatenate([points, seen[:, None].astype(np.float64)], axis=1) @ (camera.projection @ camera.view).T
    ahead = clip[:, 3] > 1e-12
    ndc = clip[:, :2] / np.where(ahead, clip[:, 3], 1.0)[:, None]
    x = (ndc[:, 0] * 0.5 + 0.5) * width - 0.5  # pixel centres at whole numbers
    y = (0.5 - ndc[:, 1] * 0.5) * height - 0.5  # rows from the top
    left, top = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    across, down = x - left, y - top
    source_position = source.position.reshape(-1, 3)
    source_normal = source.normal.reshape(-1, 3)
    taps = []
    for dy in (0, 1):
        for dx in (0, 1):
            column, row = left + dx, top + dy
            inside = ahead & (column >= 0) & (column < width) & (row >= 0) & (row < height)
            pixel = np.where(inside, row * width + column, 0)
            offset = source_position[pixel] - points
            on_plane = np.abs(np.sum(offset * normal, axis=1)) < SAME_SURFACE_FOOTPRINTS * footprint
            facing = np.sum(source_normal[pixel] * normal, axis=1) > SAME_SURFACE_NORMAL
            source_seen = source.seen.reshape(-1)[pixel]
            same = np.where(seen, source_seen & on_plane & facing, ~source_seen)
            weight = (across if dx else 1 - across) * (down if dy else 1 - down)
            taps.append((pixel, np.where(inside & same, weight, 0.0)))
    return taps


def _project(layer, taps):
    """`layer`'s samples (and the spread of its requests) where the `taps` (_lookup) find
    them, the pixels with samples alone, renormalised, flat: (residual (n, 3), samples,
    scatter, dof). What is carried over is the samples' difference from the layer's
    preview, to be added to the target's own preview: the previews hold the detail (shadow
    edges, small geometry) that resampling would blur, the difference is smooth."""
    scatter, dof = layer.scatter()
    residual = layer.sum - layer.samples[..., None] * layer.preview
    flat = [residual.reshape(-1, 3), layer.samples.reshape(-1), scatter.reshape(-1), dof.reshape(-1)]
    count = taps[0][0].shape[0]
    picked = [np.zeros_like(values, shape=(count,) + values.shape[1:]) for values in flat]
    found = np.zeros(count)
    for pixel, geometric in taps:
        weight = np.where(flat[1][pixel] > 0, geometric, 0.0)
        found += weight
        for total, values in zip(picked, flat):
            total += (weight[:, None] if values.ndim == 2 else weight) * values[pixel]
    share = np.where(found > 0, 1.0 / np.maximum(found, 1e-30), 0.0)  # the surface's neighbours alone, renormalised
    return picked[0] * share[:, None], picked[1] * share, picked[2] * share, picked[3] * share


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
    variance = _pooled_variance(luminance, samples, gathered.scatter, gathered.dof)
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
    own_weight = 1.0  # the cascade's weight of a pixel's own samples in its estimate
    edges = guide.edges
    for level in range(SCALES + 1):
        if level:
            numerator, denominator, spread = edges.filter(numerator, denominator, spread, 2 ** (level - 1))
            own_weight *= _Edges.KERNEL[1] ** 2
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
    risk_choice = np.where(np.isfinite(risk)[..., None], risk_choice, chosen)
    known = np.isfinite(chosen_variance)
    # the two rules' estimates averaged: no worse than their mean error, and either's
    # misjudged pixels halved
    correction = 0.5 * (chosen + risk_choice) * scale
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
        taps[0], taps[step], taps[-1] = _Edges.KERNEL
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
    own variation counts too: conservative), a pixel far off it (a firefly) given its own."""
    repeated = _box_sum(dof, radius)
    window_spread = np.maximum(_box_sum(scatter, radius), 0.0) / np.maximum(repeated, 1.0)
    own_spread = scatter / np.maximum(dof, 1.0)
    measured = np.maximum(window_spread, own_spread)  # a firefly's requests spread it
    sampled = (samples > 0).astype(np.float64)
    weights = _box_sum(samples, radius)
    first = _box_sum(samples * luminance, radius)
    second = _box_sum(samples * luminance * luminance, radius)
    count = _box_sum(sampled, radius)
    spread = second - first * first / np.maximum(weights, 1e-30)
    pooled = np.where(count > 1, np.maximum(spread, 0.0) / np.maximum(count - 1, 1.0), np.nan)
    fallback = np.nanmax(pooled) if np.any(np.isfinite(pooled)) else 1.0
    pooled = np.where(np.isfinite(pooled), pooled, fallback)
    own = samples * (luminance - first / np.maximum(weights, 1e-30)) ** 2
    spatial = np.where(own > OUTLIER * pooled, own, pooled)
    # a firefly in one of a pixel's few requests hardly spreads their means (the larger
    # request holds it and the mean): the pixel is judged against its window's then too,
    # but a detail every request shows (a window's edge, a lamp's speck) spreads them no
    # more than noise does
    firefly = (dof < NOISE_DOF) & (own > OUTLIER * np.maximum(pooled, measured))
    firefly &= (dof < AGREEING_DOF) | (own_spread > OUTLIER * window_spread)
    return np.where(repeated >= NOISE_DOF, np.where(firefly, own, measured), spatial)


class _Edges:
    """The G-buffer's edges for the à-trous filter: a 3 × 3 B-spline kernel at a step,
    neighbours weighted by plane distance and normals, surfaces and background apart. The
    weights depend on the guide alone: made once a view (Guide.edges), whatever the samples."""

    KERNEL = (0.25, 0.5, 0.25)

    def __init__(self, guide):
        self.position = guide.position.astype(np.float32)
        self.normal = guide.normal.astype(np.float32)
        self.seen = guide.seen
        self.footprint = guide.footprint.astype(np.float32)
        self.taps = {}  # step -> [(target slices, source slices, weight)]

    def _taps(self, step):
        if step not in self.taps:
            height, width = self.seen.shape
            taps = []
            for dy, ky in zip((-1, 0, 1), self.KERNEL):
                for dx, kx in zip((-1, 0, 1), self.KERNEL):
                    oy, ox = dy * step, dx * step
                    target = (slice(max(0, -oy), height - max(0, oy)), slice(max(0, -ox), width - max(0, ox)))
                    source = (slice(max(0, oy), height + min(0, oy)), slice(max(0, ox), width + min(0, ox)))
                    if target[0].start < target[0].stop and target[1].start < target[1].stop:
                        taps.append((target, source, ky * kx * self._edge(target, source, step)))
            self.taps[step] = taps
        return self.taps[step]

    def filter(self, numerator, denominator, spread, step):
        sums = [np.zeros_like(numerator), np.zeros_like(denominator), np.zeros_like(spread)]
        for target, source, weight in self._taps(step):
            sums[0][target] += weight[..., None] * numerator[source]
            sums[1][target] += weight * denominator[source]
            sums[2][target] += weight * weight * spread[source]
        return sums

    def _edge(self, at, neighbour, step):
        if at == neighbour:
            return np.ones(self.seen[at].shape, np.float32)
        seen = self.seen[at]
        normal = self.normal[at]
        offset = self.position[neighbour] - self.position[at]
        plane = np.abs(np.einsum("...k,...k->...", offset, normal)) / (PLANE_FOOTPRINTS * step * self.footprint[at]
                                                                        + 1e-30)
        alike = np.clip(np.einsum("...k,...k->...", normal, self.normal[neighbour]), 0.0, 1.0)
        for _ in range(int(np.log2(NORMAL_POWER))):
            alike *= alike
        surface = np.exp(-plane) * alike
        return np.where(seen == self.seen[neighbour], np.where(seen, surface, 1.0), 0.0)


CASCADE_VARIANCE = _cascade_variance(SCALES)
