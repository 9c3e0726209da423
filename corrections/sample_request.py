"""A request for Cycles samples of a region of a view, and what a worker sends back:
plain data, pickled between the master and the workers."""
from dataclasses import dataclass, field

from ..gpu.errors import LPVError


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


@dataclass
class SampleResult:
    """The request's passes (name -> (y1 - y0, x1 - x0, 3) float32, top row first) and
    the seconds its render took."""

    request: SampleRequest
    passes: dict = field(repr=False)
    seconds: float = 0.0
