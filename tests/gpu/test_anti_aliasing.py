"""Anti-aliasing: the VPL sets a frame averages look through points of the pixel drawn
from Blender's pixel filter, so a still frame's silhouettes get the intermediate pixels
Cycles' have; the first set looks through the pixels' centres."""
import numpy as np

from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.pixel_filter import pixel_offset
from lpv_preview.gpu.scene import Camera, Film, Light, Scene
from lpv_preview.gpu.settings import Settings


def test_the_offsets_cover_the_filter_evenly_and_the_first_is_the_centre():
    assert pixel_offset(0, 1.5) == (0.0, 0.0)
    offsets = np.array([pixel_offset(index, 1.5) for index in range(1, 257)])
    assert np.all(np.abs(offsets) <= 0.75)
    assert np.all(np.abs(offsets.mean(axis=0)) < 0.02)
    x = np.linspace(0.0, 1.0, 10001)  # the Blackman-Harris window's own spread over 1.5 pixels
    window = 0.35875 - 0.48829 * np.cos(2 * np.pi * x) + 0.14128 * np.cos(4 * np.pi * x) - 0.01168 * np.cos(6 * np.pi * x)
    spread = 1.5 * np.sqrt(np.sum((x - 0.5) ** 2 * window) / np.sum(window))
    assert np.all(np.abs(offsets.std(axis=0) / spread - 1) < 0.05)
    assert pixel_offset(5, 0.0) == (0.0, 0.0)


def tilted_card(film):
    """A white card tilted across the view, lit from the front, on a black background."""
    corners = np.array([[-1.0, 0.0, -0.8], [1.0, 0.0, -0.6], [0.9, 0.0, 0.9], [-0.8, 0.0, 0.7]])
    triangles = np.array([corners[[0, 1, 2]], corners[[0, 2, 3]]])
    light = Light("POINT", (0.0, -2.0, 0.0), (0, 1, 0), (0, 0, 1), (1, 1, 1), 200.0)
    camera = Camera.look_at((0.05, -3.0, 0.02), (0.0, 0.0, 0.0), fov_y=0.9, aspect=1.0, near=0.1, far=10.0)
    return Scene(triangles, np.zeros_like(triangles), np.full((2, 3), 0.8), [light], camera, film=film).sanitize()


def test_a_still_frame_smooths_its_silhouettes_over_its_sets():
    settings = Settings(width=48, height=48, rsm_resolution=64, vpls_per_light=256, lpv_resolution=16)
    one = render_once(tilted_card(Film()), settings.with_changes(converge_sets=1))
    many = render_once(tilted_card(Film()), settings.with_changes(converge_sets=16))
    rows = int((one.coverage.max(axis=1) > 0).sum())  # the rows the card crosses
    assert set(np.unique(one.coverage)) == {0.0, 1.0}  # one sample at each pixel's centre
    partial = (many.coverage > 0.02) & (many.coverage < 0.98)
    assert int(np.any(partial, axis=1).sum()) >= rows - 2  # every row the card crosses has a soft edge
    edge = many.passes["combined"].mean(axis=-1)[partial]
    inside = many.passes["combined"].mean(axis=-1)[many.coverage == 1.0]
    assert np.all(edge > 0) and np.median(edge) < np.median(inside)
    assert abs(many.passes["combined"].mean() / one.passes["combined"].mean() - 1) < 0.05


def test_a_wider_filter_blurs_more():
    settings = Settings(width=48, height=48, rsm_resolution=64, vpls_per_light=256, lpv_resolution=16,
                        converge_sets=16)
    narrow = render_once(tilted_card(Film(filter_width=0.5)), settings).coverage
    wide = render_once(tilted_card(Film(filter_width=3.0)), settings).coverage
    partial = lambda alpha: int(((alpha > 0.02) & (alpha < 0.98)).sum())  # noqa: E731
    assert partial(wide) > 1.5 * partial(narrow)
