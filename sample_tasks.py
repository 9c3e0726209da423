"""The task a Cycles sample worker runs (addon/sample_workers.py) and its request and
result, importable without bpy:
a Dask worker process unpickles it before anything else, and `lpv_preview.addon` imports
bpy, which must first find the module, not Blender's own scripts' package of that name
(a worker process starts with its parent's sys.path, where `import bpy` put them)."""
import atexit
import os
import re
import sys
from dataclasses import dataclass

from .gpu.errors import LPVError

BLENDER_SCRIPTS = re.compile(r"[/\\]bpy[/\\][0-9.]+[/\\]scripts")
"""The folders of Blender's own scripts, which `import bpy` puts on sys.path."""
_RENDERERS = {}  # in a worker process: (.blend path, its modification time and size) -> SampleRenderer


@dataclass(frozen=True)
class SampleRequest:
    """Samples of the pixels `region` (x0, y0, x1, y1: columns x0..x1-1 and rows y0..y1-1
    of a `resolution` (width, height) image, row 0 at the top) seen by a camera whose
    world matrix is `camera` (4 × 4 nested tuples; None: the scene's own) through the
    OpenGL perspective `projection` (4 × 4 nested tuples, unshifted, the image's aspect;
    None: the scene camera's own lens), `samples` a pixel with the sampling pattern of
    `seed`, at the animation's frame `scene_frame` (None: where the worker's scene is, the
    file's own frame until a request sets another);
    `denoise`d by OpenImageDenoise as Cycles' viewport denoises (what the corrections are
    measured against)."""

    region: tuple
    resolution: tuple
    samples: int
    seed: int = 0
    camera: tuple = None
    projection: tuple = None
    denoise: bool = False
    scene_frame: int = None

    def __post_init__(self):
        x0, y0, x1, y1 = self.region
        width, height = self.resolution
        if not (0 <= x0 < x1 <= width and 0 <= y0 < y1 <= height) or self.samples < 1:
            raise LPVError(f"A Cycles sample request of region {self.region} in a {width} x {height} image with "
                           f"{self.samples} samples is out of range; ask for pixels inside the image, 1 sample or "
                           f"more.")
        if self.projection is not None:
            check_projection(self.projection, self.resolution)


def check_projection(projection, resolution):
    """Refuse an OpenGL projection Cycles' camera cannot take: not perspective, shifted, or
    of another aspect than the `resolution` (width, height)."""
    width, height = resolution
    p = projection
    aspect = max(0.01, 1.0 / min(width, height))  # sizes are whole pixels
    if p[3][2] != -1 or abs(p[0][2]) > 1e-6 or abs(p[1][2]) > 1e-6 or abs(p[1][1] / p[0][0] * height / width - 1) > aspect:
        raise LPVError("Cycles samples are taken through unshifted perspective views of the image's aspect only; "
                       "leave the orthographic or shifted view to correct it.")


def close_renderers():
    """In a worker: remove the renderer's folder as the process ends (a studio's long-lived
    worker; a local cluster removes its workers' whole folder anyway)."""
    for opened in _RENDERERS.values():
        opened.close()
    _RENDERERS.clear()


atexit.register(close_renderers)


def renderer(blend_path):
    """In a worker: its SampleRenderer of the .blend at `blend_path`, opened once a process."""
    if "bpy" not in sys.modules:
        sys.path.sort(key=lambda folder: bool(BLENDER_SCRIPTS.search(folder)))  # the module's folder first
    from .addon.cycles_samples import SampleRenderer
    try:
        saved = os.stat(blend_path)
        key = (blend_path, saved.st_mtime_ns, saved.st_size)  # a file saved again is opened again
    except OSError:
        key = (blend_path,)  # SampleRenderer says there is none
    if key not in _RENDERERS:
        close_renderers()
        _RENDERERS[key] = SampleRenderer(blend_path)
    return _RENDERERS[key]


def open_blend(blend_path):
    """In a worker: open the .blend now (before requests come)."""
    renderer(blend_path)


def render_request(blend_path, request, threads=None):
    """In a worker: the SampleResult of `request` on the .blend at `blend_path`, Cycles on
    `threads` threads (None: all the machine's)."""
    return renderer(blend_path).render(request, threads)
