"""A seeded scene fuzzer: random triangle soups the way broken files and odd scenes make
them (slivers, huge and tiny triangles, duplicate and coplanar faces, lights inside, on
and outside geometry, cameras inside objects, scales from 1e-4 to 1e6, far from the
world origin), each rendered by a random method at a small size. Every case must end in
finite, non-negative passes whose indirect light stays under what the lights' power
could give (`indirect_bound`), or in one LPVError sentence; anything else is a failure
with its seed, so it can be replayed.
"""
import math
import time
import traceback

import numpy as np

from ..gpu.errors import LPVError
from ..gpu.lpv import LOBE_C0
from ..gpu.pipeline import Pipeline
from ..gpu.scene import LIGHT_KINDS, Camera, Light, Scene
from ..gpu.settings import METHODS, Settings

SETTINGS = Settings(width=24, height=24, rsm_resolution=32, vpls_per_light=64, lpv_resolution=8,
                    propagation_iterations=4, converge_sets=1)


def random_scene(seed):
    """The scene of `seed`: a few groups of triangles of one random kind each."""
    rng = np.random.default_rng(seed)
    scale = 10.0 ** rng.uniform(-4, 6)
    offset = rng.choice([0.0, 1.0]) * 10.0 ** rng.uniform(0, 6) * rng.normal(size=3)
    groups = []
    for _ in range(rng.integers(1, 5)):
        kind = rng.choice(["soup", "slivers", "huge", "tiny", "duplicates", "coplanar", "box"])
        count = int(rng.integers(1, 40))
        points = rng.normal(size=(count, 3, 3))
        if kind == "slivers":
            points[:, 2] = points[:, 0] + (points[:, 1] - points[:, 0]) * rng.uniform(0, 1, (count, 1)) \
                + rng.normal(scale=10.0 ** rng.uniform(-9, -3), size=(count, 3))
        elif kind == "huge":
            points *= 1e3
        elif kind == "tiny":
            points = points[:, :1] + points * 1e-6
        elif kind == "duplicates":
            points = np.repeat(points[:1], count, axis=0)
        elif kind == "coplanar":
            points[..., 2] = 0.0
        elif kind == "box":
            points = _box(rng.normal(size=3), rng.uniform(0.1, 2.0))
        groups.append(points)
    triangles = np.concatenate(groups) * scale + offset
    normals = rng.normal(size=triangles.shape) * rng.choice([0.0, 1.0])  # broken normals half the time
    albedo = rng.uniform(0, 1.2, size=(len(triangles), 3))
    lights = [_random_light(rng, triangles, scale) for _ in range(rng.integers(0, 4))]
    eye = triangles[rng.integers(len(triangles))].mean(axis=0) + rng.normal(size=3) * scale * rng.choice([0.0, 3.0])
    target = eye + rng.normal(size=3)
    up = rng.normal(size=3)
    camera = None
    if np.linalg.norm(np.cross(target - eye, up)) > 1e-6:
        camera = Camera.look_at(eye, target, up, near=scale * 1e-3, far=scale * 1e3 + 1.0)
    return Scene(triangles, normals, albedo, lights, camera)


def _box(centre, size):
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float64) * size
    corners += centre
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    triangles = [(a, b, c) for a, b, c, d in faces] + [(a, c, d) for a, b, c, d in faces]
    return corners[np.array(triangles)]


def _random_light(rng, triangles, scale):
    """A light inside, on or outside the geometry, of any kind and power."""
    kind = LIGHT_KINDS[rng.integers(len(LIGHT_KINDS))]
    where = rng.choice(["vertex", "inside", "outside"])
    if where == "vertex":
        position = triangles[rng.integers(len(triangles)), rng.integers(3)]
    elif where == "inside":
        position = triangles.reshape(-1, 3).mean(axis=0)
    else:
        position = triangles.reshape(-1, 3).mean(axis=0) + rng.normal(size=3) * scale * 10
    direction = rng.normal(size=3)
    return Light(kind, position, direction, rng.normal(size=3), rng.uniform(0, 1, 3), 10.0 ** rng.uniform(-3, 4) *
                 (1.0 if kind == "SUN" else scale ** 2), spot_size=rng.uniform(0.01, math.pi),
                 size=tuple(rng.uniform(0, 2, 2) * scale), name=f"fuzz {kind.lower()}")


def indirect_bound(scene, frame, settings):
    """The most indirect radiance any pixel could get: every light's power reflected
    (a sun's over the scene's bounding square), injected into one cell and gathered there
    after every propagation step, at the largest albedo (1 after sanitizing)."""
    low, high = scene.bounds()
    reach = float(np.max(high - low)) + 1e-30
    flux = sum(float(np.max(light.rgb_power)) * (4 * reach ** 2 if light.kind == "SUN" else 1.0)
               for light in scene.lights)
    cell = frame.stats["lpv_cell_size"]
    lobe = 2 * LOBE_C0  # |cos lobe| with both bands, generously
    return (settings.propagation_iterations + 1) * flux / math.pi * lobe * lobe / cell ** 2 / math.pi


def check_case(seed, glc=None):
    """Render the scene of `seed`; returns (outcome, detail): "rendered", "refused" (one
    LPVError sentence) or "failed"."""
    rng = np.random.default_rng(seed + 1_000_003)
    settings = SETTINGS.with_changes(method=METHODS[rng.integers(len(METHODS))])
    try:
        scene = random_scene(seed)
        pipeline = Pipeline(settings, glc)
        try:
            frame = pipeline.render(scene)
        finally:
            pipeline.release()
    except LPVError as error:
        message = str(error)
        single = "\n" not in message and message.endswith(".")
        return ("refused", message) if single else ("failed", f"an LPVError of more than one sentence: {message}")
    except Exception:  # noqa: BLE001  (the fuzzer's point: name whatever else escapes)
        return "failed", traceback.format_exc(limit=3)
    for name, image in frame.passes.items():
        if not np.all(np.isfinite(image)) or image.min() < 0:
            return "failed", f"{settings.method}: the {name} pass has non-finite or negative pixels"
    bound = indirect_bound(scene, frame, settings)
    if frame.passes["indirect"].max() > bound:
        return "failed", f"{settings.method}: indirect {frame.passes['indirect'].max():.3g} above the bound {bound:.3g}"
    return "rendered", settings.method


def fuzz(seeds, seconds=None, glc=None, log=None):
    """Run `check_case` over `seeds` (stopping after `seconds` when given); returns counts
    of each outcome and the failures with their seeds."""
    started = time.perf_counter()
    counts = {"rendered": 0, "refused": 0, "failed": 0}
    failures, refusals = [], {}
    for seed in seeds:
        if seconds is not None and time.perf_counter() - started > seconds:
            break
        outcome, detail = check_case(seed, glc)
        counts[outcome] += 1
        if outcome == "failed":
            failures.append({"seed": seed, "detail": detail})
        elif outcome == "refused":
            refusals[detail] = refusals.get(detail, 0) + 1
        if log is not None and sum(counts.values()) % 100 == 0:
            log(f"fuzz: {sum(counts.values())} scenes, {counts}")
    return {"counts": counts, "failures": failures, "refusals": refusals,
            "seconds": time.perf_counter() - started}
