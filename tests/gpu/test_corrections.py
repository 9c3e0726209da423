"""Corrective texturing (issue 18, seed 001): the reconstruction of sparse, noisy samples
guided by the G-buffer, the layers that keep the corrections over a camera move, and the
priority queue of requests. Scenes of numpy arrays: a floor and a wall seen by a camera,
ray-cast here; the samples are the true image plus noise, as Cycles' are."""
import math

import numpy as np
import pytest

from lpv_preview.corrections.request_queue import DONE_ERROR, DONE_SAMPLES, PIXEL_SAMPLES, RequestQueue
from lpv_preview.corrections.guide import Guide
from lpv_preview.corrections.layers import LAYER_AGING, MAX_LAYERS, Corrections, Gathered, Layer
from lpv_preview.corrections.reconstruction import reconstruct
from lpv_preview.gpu.errors import LPVError
from lpv_preview.gpu.metrics import RELATIVE_EPSILON, relative_mse
from lpv_preview.gpu.scene import Camera

SIZE = (64, 48)


def corner_guide(camera, size=SIZE):
    """The Guide of a camera looking at a floor z = 0 and a wall y = 4 (grey albedo, a
    darker stripe on the floor), ray-cast per pixel."""
    width, height = size
    inverse = np.linalg.inv(camera.projection @ camera.view)
    xs = (np.arange(width) + 0.5) / width * 2 - 1
    ys = 1 - (np.arange(height) + 0.5) / height * 2  # top row first
    ndc = np.stack(np.meshgrid(xs, ys) + [np.ones((height, width)), np.ones((height, width))], axis=-1)
    far = ndc @ inverse.T
    eye = camera.position
    direction = far[..., :3] / far[..., 3:] - eye
    direction /= np.linalg.norm(direction, axis=-1, keepdims=True)
    t_floor = np.where(direction[..., 2] < -1e-9, -eye[2] / np.minimum(direction[..., 2], -1e-9), np.inf)
    t_wall = np.where(direction[..., 1] > 1e-9, (4 - eye[1]) / np.maximum(direction[..., 1], 1e-9), np.inf)
    t = np.minimum(t_floor, t_wall)
    seen = np.isfinite(t)
    position = np.where(seen[..., None], eye + direction * np.where(seen, t, 0)[..., None], direction)
    on_floor = t_floor <= t_wall
    normal = np.where(on_floor[..., None], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]) * seen[..., None]
    albedo = np.where((on_floor & (np.abs(position[..., 0]) < 0.3))[..., None], 0.2, 0.7) * np.ones(3) * seen[..., None]
    footprint = np.where(seen, t, 0) * camera.pixel_angle(height)
    return Guide(*(a.astype(np.float32) for a in (position, normal, albedo)), seen, footprint.astype(np.float32))


def truth_of(guide):
    """The 'Cycles' image: the albedo times an irradiance that varies smoothly over each surface."""
    irradiance = 1.0 + 0.5 * np.sin(guide.position[..., :1]) + 0.1 * guide.position[..., 1:2]
    return (guide.albedo * irradiance * guide.seen[..., None]).astype(np.float64)


def noisy_requests(truth, samples, rng, requests=4, sigma=0.6):
    """The images of `requests` requests of `samples` noisy samples a pixel."""
    return [truth + rng.normal(0.0, sigma, truth.shape) * truth / math.sqrt(samples) for _ in range(requests)]


def gathered(guide, images, samples, region=None):
    """The Gathered samples of requests whose images are `images` (of the whole view), of
    `samples` a pixel (one count for all, or one each), as a layer holds them; with
    `region` (x0, y0, x1, y1), of that region alone."""
    x0, y0, x1, y1 = region or (0, 0, *guide.size)
    layer = Layer(None, guide, np.zeros(guide.albedo.shape))
    for image, count in zip(images, np.broadcast_to(samples, len(images))):
        layer.add((x0, y0, x1, y1), image[y0:y1, x0:x1], int(count))
    return Gathered(layer.sum, layer.samples, *layer.scatter())


@pytest.fixture(scope="module")
def camera():
    return Camera.look_at((0.0, -3.0, 1.5), (0.0, 2.0, 0.5), fov_y=math.radians(50), aspect=SIZE[0] / SIZE[1])


def test_corrections_converge_and_beat_the_raw_samples(camera):
    """A preview 40 % too dark on the floor is corrected: better than the noisy samples'
    own mean at every count, and within a tenth of the preview's error at 64 samples."""
    guide = corner_guide(camera)
    truth = truth_of(guide)
    preview = truth * np.where(guide.normal[..., 2:] > 0.5, 0.6, 1.0)
    rng = np.random.default_rng(1)
    errors = []
    for count in (1, 4, 16, 64):
        images = noisy_requests(truth, count, rng)
        corrected = reconstruct(gathered(guide, images, count), preview, guide).image
        errors.append(relative_mse(corrected, truth))
        assert errors[-1] < relative_mse(np.mean(images, axis=0), truth), count
    assert errors[-1] < 0.1 * relative_mse(preview, truth)
    assert errors[-1] < errors[0]
    exact = reconstruct(gathered(guide, [truth] * 4, 1000), preview, guide).image  # noiseless: the samples exactly
    assert relative_mse(exact, truth) < 1e-6


def test_no_samples_leave_the_preview(camera):
    guide = corner_guide(camera)
    preview = truth_of(guide) * 0.5
    result = reconstruct(Gathered.empty(*preview.shape[:2]), preview, guide)
    np.testing.assert_array_equal(result.image, preview.astype(np.float32))
    assert result.estimated_error > 0
    assert "edges" not in guide.__dict__  # nothing to rebuild: no filter was made
    fresh = corner_guide(camera)  # a view before any sample: the same, without the rebuild
    corrections = Corrections()
    corrections.view("view", camera, fresh, preview)
    shortcut = corrections.reconstruct("view")
    assert "edges" not in fresh.__dict__  # no filter was made
    for name in ("image", "correction", "samples", "error", "estimated_error"):
        np.testing.assert_allclose(getattr(shortcut, name), getattr(result, name), rtol=1e-6, err_msg=name)


def test_a_firefly_in_the_larger_of_two_requests_is_not_kept(camera):
    """One sample 400 times the light in a pixel's second request of 16 (after one of 1)
    hardly spreads the two requests' means: the pixel is still judged a firefly against
    its window and its samples spread, not shown as a speck."""
    guide = corner_guide(camera)
    truth = truth_of(guide)
    preview = truth * 0.8
    rng = np.random.default_rng(5)
    first, second = noisy_requests(truth, 1, rng, requests=1)[0], noisy_requests(truth, 16, rng, requests=1)[0]
    row, column = 30, 20  # on the floor, away from its stripe
    second[row, column] += 400 * truth[row, column] / 16
    corrected = reconstruct(gathered(guide, [first, second], (1, 16)), preview, guide).image
    assert corrected[row, column].mean() < 3 * truth[row, column].mean()
    assert relative_mse(corrected, truth) < relative_mse(preview, truth)


def test_a_firefly_in_the_larger_of_three_requests_is_not_kept(camera):
    """One sample 400 times the light in a pixel's third request (of 1, 1 and 16 samples)
    hardly spreads their means against its own deviation, but far more than its window's
    spread: still a firefly, though three requests could tell a detail they agree on."""
    guide = corner_guide(camera)
    truth = truth_of(guide)
    preview = truth * 0.8
    rng = np.random.default_rng(6)
    images = [noisy_requests(truth, samples, rng, requests=1)[0] for samples in (1, 1, 16)]
    row, column = 30, 20
    images[-1][row, column] += 400 * truth[row, column] / 16
    corrected = reconstruct(gathered(guide, images, (1, 1, 16)), preview, guide).image
    assert corrected[row, column].mean() < 3 * truth[row, column].mean()


def test_a_detail_every_request_shows_is_kept(camera):
    """Specks twice as bright as their floor, in neither the preview nor the G-buffer, stand
    out of their windows alike in each of a pixel's first four requests (1, 1, 2 and 4
    samples): they are kept as detail, not spread as fireflies."""
    guide = corner_guide(camera)
    preview = truth_of(guide) * 0.8
    truth = truth_of(guide)
    specks = (slice(28, 44, 5), slice(8, 56, 6))  # on the floor, a few pixels apart
    truth[specks] *= 2.0
    for seed in range(3):
        rng = np.random.default_rng(seed)
        images = [noisy_requests(truth, samples, rng, requests=1, sigma=0.3)[0] for samples in (1, 1, 2, 4)]
        corrected = reconstruct(gathered(guide, images, (1, 1, 2, 4)), preview, guide).image
        kept = (corrected[specks] - preview[specks]).mean(-1) / (truth[specks] - preview[specks]).mean(-1)
        assert np.median(kept) > 0.6, seed


def test_a_darker_pixel_no_sample_reached_takes_the_correction_scaled_down(camera):
    """Samples of the view's left half (floor and wall), lit four times as brightly as its
    right, whose preview misses 40 % of the light everywhere: the right half, no sample of
    its own yet (as before the first requests have all come back), takes the left's
    correction scaled down by its lighting over theirs, not the left's missing light, which
    its assumed error ruled out (no correction at all)."""
    guide = corner_guide(camera)
    truth = truth_of(guide) * np.where(guide.position[..., :1] < 0, 4.0, 1.0)
    preview = truth * 0.6
    width, height = guide.size
    images = noisy_requests(truth, 4, np.random.default_rng(2), sigma=0.3)
    corrected = reconstruct(gathered(guide, images, 4, region=(0, 0, width // 2, height)), preview, guide).image
    right = np.s_[:, width // 2 + 4:]  # a few columns from the sampled half on
    assert relative_mse(corrected[right], truth[right]) < 0.1 * relative_mse(preview[right], truth[right])


def test_a_correction_stops_at_the_geometry_edges(camera):
    """Samples of the floor alone say nothing of the wall: it keeps its preview."""
    guide = corner_guide(camera)
    truth = truth_of(guide)
    preview = truth * 0.5
    floor = guide.normal[..., 2] > 0.5
    samples = gathered(guide, noisy_requests(truth, 16, np.random.default_rng(2)), 16)
    for values in (samples.total, samples.samples, samples.scatter, samples.dof):
        values[~floor] = 0.0
    corrected = reconstruct(samples, preview, guide).image
    wall = guide.seen & ~floor
    np.testing.assert_allclose(corrected[wall], preview[wall], rtol=1e-5)
    assert relative_mse(corrected, truth, mask=floor) < 0.2 * relative_mse(preview, truth, mask=floor)


def test_layers_carry_corrections_over_a_turn(camera):
    """Samples taken at one view land on the same surfaces seen from a view turned 5°:
    the turned frame is corrected before it has any sample of its own."""
    turn = np.eye(4)
    angle = math.radians(5)
    turn[:2, :2] = [[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]]
    eye = camera.position
    view = camera.view @ np.linalg.inv(np.block([[np.eye(3), eye[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]])
                                       @ turn @ np.block([[np.eye(3), -eye[:, None]],
                                                          [np.zeros((1, 3)), np.ones((1, 1))]]))
    turned = Camera(view, camera.projection)
    first, second = corner_guide(camera), corner_guide(turned)
    corrections = Corrections()
    truth = truth_of(first)
    corrections.view("first", camera, first, truth * 0.6)
    for image in noisy_requests(truth, 64, np.random.default_rng(3)):
        corrections.add("first", (0, 0, *SIZE), image, 64)
    truth_second = truth_of(second)
    preview = truth_second * 0.6
    corrections.view("second", turned, second, preview)
    weights = corrections.gathered("second").samples
    assert np.mean(weights[second.seen] > 0) > 0.85  # all but the strip the turn reveals
    corrected = corrections.reconstruct("second").image
    assert relative_mse(corrected, truth_second) < 0.2 * relative_mse(preview, truth_second)
    assert corrections.layers["first"].weight == 1.0 and "second" not in corrections.layers
    corrections.add("second", (0, 0, 4, 4), truth_second[:4, :4], 1)  # its first samples age the others
    assert corrections.layers["first"].weight == LAYER_AGING


def test_other_preview_settings_drop_what_other_views_carry(camera):
    """The preview's settings change: a view keeps its own samples (Cycles' do not depend on
    the preview) but not what another view's layer carries over, a difference from a
    preview of the old settings."""
    guide = corner_guide(camera)
    truth = truth_of(guide)
    corrections = Corrections()
    corrections.view("other", camera, guide, truth * 0.6, "old")
    corrections.add("other", (0, 0, *SIZE), truth, 64)
    corrections.view("here", camera, guide, truth * 0.6, "old")
    corrections.add("here", (0, 0, *SIZE), truth, 64)
    corrections.view("other", camera, guide, truth * 0.6, "old")  # the same settings: everything kept
    assert list(corrections.layers) == ["other", "here"]
    corrections.view("here", camera, guide, truth * 0.9, "new")
    assert list(corrections.layers) == ["here"] and list(corrections.views) == ["here"]
    assert relative_mse(corrections.reconstruct("here").image, truth) < 1e-4  # 'other' would carry 0.4 of it


def test_old_layers_are_dropped_and_bad_samples_left_out():
    corrections = Corrections()
    guide = Guide(*(np.zeros((4, 4, 3), np.float32) for _ in range(3)), np.zeros((4, 4), bool),
                  np.zeros((4, 4), np.float32))
    for index in range(MAX_LAYERS + 2):
        corrections.view(index, None, guide, np.zeros((4, 4, 3)))
        corrections.add(index, (0, 0, 1, 1), np.ones((1, 1, 3)), 1)
    assert list(corrections.layers) == list(range(2, MAX_LAYERS + 2))
    assert corrections.layers[2].weight == LAYER_AGING ** (MAX_LAYERS - 1)
    assert not corrections.add(0, (0, 0, 1, 1), np.zeros((1, 1, 3)), 1)  # a forgotten view's samples are let go
    with pytest.raises(LPVError, match="another image than asked"):
        corrections.add(MAX_LAYERS + 1, (0, 0, 2, 2), np.zeros((1, 2, 3)), 1)
    corrections.add(MAX_LAYERS + 1, (0, 0, 2, 1), np.array([[[np.nan, 0, 0], [2.0, 2.0, 2.0]]]), 4)
    layer = corrections.layers[MAX_LAYERS + 1]
    assert layer.samples[0, :2].tolist() == [1.0, 4.0] and np.all(np.isfinite(layer.sum))


def test_the_queue_covers_the_view_first_then_follows_the_error():
    queue = RequestQueue((128, 96))
    queue.update(np.full((96, 128), 0.25), np.zeros((96, 128)), np.zeros((96, 128)))  # the preview's assumed error
    first = [queue.next() for _ in range(len(queue.tiles))]
    covered = np.zeros((96, 128), bool)
    for (x0, y0, x1, y1), _ in first:
        covered[y0:y1, x0:x1] = True
    assert covered.all()  # the uniform requests: every pixel before any pixel twice
    assert first[0][1] == 1 and first[0][0][2] - first[0][0][0] == 128  # a row of tiles at 1 sample a pixel
    for region, spp in first:
        queue.done(region, spp, 0.05)
    error = np.full((96, 128), 1e-4)
    error[64:96, 96:128] = 0.5  # one corner is far off
    samples = np.zeros((96, 128))
    for (x0, y0, x1, y1), spp in first:
        samples[y0:y1, x0:x1] += spp
    queue.update(error, samples, samples)
    region, spp = queue.next()
    x0, y0, x1, y1 = region
    assert x1 > 96 and y1 > 64 and 2 * spp > samples[y0:y1, x0:x1].mean()  # there, about doubling its samples


def test_a_pixels_requests_grow_evenly():
    """Whatever the errors, no request asks a tile for more than 4 times the samples it
    holds: the spread of a pixel's requests then tells their noise (two of 1 and 16 did not)."""
    queue = RequestQueue((128, 96))
    rng = np.random.default_rng(6)
    samples = np.zeros((96, 128))
    for _ in range(40):
        queue.update(rng.uniform(0.0, 1.0, (96, 128)), samples, samples)
        (x0, y0, x1, y1), spp = queue.next()
        held = samples[y0:y1, x0:x1].max()
        assert spp <= 4 * max(held, 1.0), (held, spp)
        queue.done((x0, y0, x1, y1), spp, 0.05)
        samples[y0:y1, x0:x1] += spp


def test_the_queue_stops_when_every_tile_has_its_samples_or_no_error_left():
    queue = RequestQueue((64, 64))
    queue.update(np.full((64, 64), 0.25), *[np.full((64, 64), float(PIXEL_SAMPLES))] * 2)
    assert queue.next() is None
    samples = np.full((64, 64), float(PIXEL_SAMPLES))
    samples[:16, :16] = 0.0
    queue.update(np.full((64, 64), 0.25), samples, samples)
    region, _ = queue.next()
    assert region[:2] == (0, 0)
    low = np.full((64, 64), 0.5 * DONE_ERROR)
    queue.update(low, np.full((64, 64), 64.0), np.zeros((64, 64)))  # carried over from other views alone
    assert queue.next() is not None  # their resampling's error is not in the estimate
    queue = RequestQueue((64, 64))
    queue.update(low, *[np.full((64, 64), float(DONE_SAMPLES))] * 2)  # its own, and nothing left to see
    assert queue.next() is None


def first_samples(truth, rng, hit=0.1):
    """One sample a pixel as a path tracer's first often is: black, or 1 / `hit` times the
    light (its mean is the light; most pixels show less)."""
    return truth * rng.binomial(1, hit, truth.shape[:2])[..., None] / hit


def block_errors(image, truth, block=16):
    """The relative MSE of each block × block block."""
    height, width = truth.shape[:2]
    squared = ((image - truth) ** 2 / (truth ** 2 + RELATIVE_EPSILON)).mean(-1)
    rows, columns = height // block, width // block
    return squared[:rows * block, :columns * block].reshape(rows, block, columns, block).mean((1, 3))


@pytest.mark.parametrize("hit", [0.5, 0.2, 0.05])
def test_one_sample_a_pixel_makes_no_part_of_the_frame_worse_than_its_preview(hit):
    """A first request of one sample a pixel, most of them black and a few bright: no block
    of the corrected frame errs more than the preview's (the preview shows where the
    correction is within its noise), and a preview that is right stays right."""
    size = (128, 96)
    camera = Camera.look_at((0.0, -3.0, 1.5), (0.0, 2.0, 0.5), fov_y=math.radians(50), aspect=size[0] / size[1])
    guide = corner_guide(camera, size)
    truth = truth_of(guide)
    for seed in range(3):
        samples = gathered(guide, [first_samples(truth, np.random.default_rng(seed), hit)], 1)
        dark = truth * 0.8
        corrected = reconstruct(samples, dark, guide).image
        assert np.all(block_errors(corrected, truth) <= 1.1 * block_errors(dark, truth)), (hit, seed)
        assert relative_mse(corrected, truth) < relative_mse(dark, truth)
        right = reconstruct(samples, truth, guide).image
        assert relative_mse(right, truth) < 1e-3, (hit, seed)


def test_a_correction_beyond_the_samples_fades_out_without_a_seam():
    """Samples of a band of rows at the top of a wall seen straight on, whose preview misses
    20 % of the light everywhere: below the band the correction fades out row by row, with
    no step where the band ends or where the filter's reach ends (127 rows below it)."""
    size = (96, 224)
    camera = Camera.look_at((0.0, -3.0, 6.0), (0.0, 4.0, 6.0), fov_y=math.radians(70), aspect=size[0] / size[1])
    guide = corner_guide(camera, size)
    assert np.all(guide.normal[..., 1] < -0.5)  # the wall alone
    truth = truth_of(guide)
    preview = truth * 0.8
    band = 32
    images = noisy_requests(truth, 16, np.random.default_rng(3), sigma=0.3)
    result = reconstruct(gathered(guide, images, 16, region=(0, 0, size[0], band)), preview, guide)
    rows = np.median((result.correction / (truth - preview)).mean(-1), axis=1)
    assert rows[band - 4:band].min() > 0.8  # the band is corrected
    assert np.abs(np.diff(rows[band - 1:])).max() < 0.05
    assert rows[band + 127:].max() < 0.01  # beyond the reach: the preview
