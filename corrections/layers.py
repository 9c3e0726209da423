"""The Cycles samples as projective layers, one for every camera position that got
samples (the seed's corrective textures, projected from the viewpoint): per pixel the
surface seen, its preview and the samples received there, divided by the preview's albedo
(lighting varies less than texture). A view looks every other layer up from its own
pixels (`_lookup`: the same surface, within footprints along the normal, normals alike, or
background for background) and carries over the samples' difference from that layer's
preview; older layers weigh less (aging)."""
from dataclasses import dataclass

import numpy as np

from ..gpu.colour import LUMINANCE_WEIGHTS
from ..gpu.errors import LPVError
from .guide import Guide
from .reconstruction import reconstruct

SAME_SURFACE_NORMAL = 0.9
SAME_SURFACE_FOOTPRINTS = 2.0
"""A layer's pixel is the frame's surface when their normals' cosine is above
SAME_SURFACE_NORMAL and it lies within this many footprints of the frame's plane."""
LAYER_AGING = 0.5
"""Weight a layer keeps each time another view gets its first samples."""
MAX_LAYERS = 8
"""Layers kept (the oldest go), and views remembered."""

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
        """The view `key` (its gpu Camera, G-buffer as a GBufferRecord or Guide, and preview) is shown: remembered; its
        layer is made when its first samples come. Previews of other `settings` than the
        last view's leave the other layers out: what they carry over is their samples'
        difference from previews of the old settings (the view's own samples stay: Cycles'
        do not depend on the preview)."""
        guide = Guide.of(guide)
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
