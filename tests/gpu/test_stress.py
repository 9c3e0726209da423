"""Numerical stress for the paraboloid methods (issue: DPM/WDPM/TDPM/TWDPM): every case
renders finite passes, reports its warp status, and ends."""
import numpy as np
import pytest

from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene import Scene
from lpv_preview.gpu.settings import Settings

from ..synthetic_scenes import room_scene

METHODS = ("dpm", "wdpm", "tdpm", "twdpm")


def with_slivers(scene):
    """Add needle triangles 1e-4 of their length wide, fanned around the light."""
    centre = scene.lights[0].position.astype(np.float32)
    angles = np.linspace(0, 2 * np.pi, 50, endpoint=False)
    tips = np.stack([np.cos(angles), np.sin(angles), np.full_like(angles, -0.5)], 1).astype(np.float32)
    slivers = np.stack([centre + tips, centre + 2 * tips, centre + 2 * tips + np.float32(2e-4) * np.roll(tips, 1, 0)], 1)
    triangles = np.concatenate([scene.triangles, slivers])
    albedo = np.concatenate([scene.albedo, np.full((len(slivers), 3), 0.5, np.float32)])
    return Scene(triangles, np.zeros_like(triangles), albedo, scene.lights, scene.camera).sanitize()


def hemisphere_cover(scene):
    """One triangle under the light that covers most of its lower hemisphere."""
    x, y, z = scene.lights[0].position
    big = np.array([[[x - 40, y - 40, z - 0.5], [x + 40, y - 40, z - 0.5], [x, y + 60, z - 0.5]]], np.float32)
    triangles = np.concatenate([scene.triangles, big])
    albedo = np.concatenate([scene.albedo, np.full((1, 3), 0.5, np.float32)])
    return Scene(triangles, np.zeros_like(triangles), albedo, scene.lights, scene.camera).sanitize()


CASES = {
    "light exactly on the floor": lambda: room_scene(4, light_position=(0.4, -0.3, 0.0)),
    "light inside a closed box": lambda: room_scene(4),
    "a triangle covering a hemisphere": lambda: hemisphere_cover(room_scene(4)),
    "degenerate slivers": lambda: with_slivers(room_scene(4)),
    "scale 1e-3": lambda: room_scene(4, scale=1e-3),
    "scale 1e4": lambda: room_scene(4, scale=1e4),
}


@pytest.mark.parametrize("case", list(CASES))
def test_stress_case_stays_finite(case):
    scene = CASES[case]()
    figures = {}
    for method in METHODS:
        pipeline = Pipeline(Settings(width=48, height=48, rsm_resolution=64, vpls_per_light=256, method=method))
        try:
            frame = pipeline.render(scene)
        finally:
            pipeline.release()
        for name, image in frame.passes.items():
            assert np.all(np.isfinite(image)), (case, method, name)
        if method in ("wdpm", "twdpm"):
            status = frame.stats["warp_status"]
            assert sum(status.values()) == 64 * 64 * frame.stats["rsm_faces"]
            figures[method] = status
        figures[method + " indirect mean"] = float(frame.passes["indirect"].mean())
    print(f"\n{case}: {figures}")


def test_auto_picks_per_light():
    from lpv_preview.gpu.scene import Light
    scene = room_scene(4)
    point = scene.lights[0]
    narrow_spot = Light("SPOT", (0, 0, 2.5), (0, 0, -1), (0, 1, 0), (1, 1, 1), 50.0, spot_size=np.radians(60))
    wide_spot = Light("SPOT", (0, 0, 2.5), (0, 0, -1), (0, 1, 0), (1, 1, 1), 50.0, spot_size=np.radians(120))
    sun = Light("SUN", (0, 0, 0), (0.3, 0.2, -1), (0, 1, 0), (1, 1, 1), 2.0)
    scene.lights = [point, narrow_spot, wide_spot, sun]
    pipeline = Pipeline(Settings(width=32, height=32, rsm_resolution=64, vpls_per_light=128, method="auto"))
    try:
        frame = pipeline.render(scene)
        maps, _ = pipeline.light_maps(scene)
    finally:
        pipeline.release()
    methods = frame.stats["light_methods"]
    print(f"\nauto chose {methods}")
    assert methods[1] == "cm" and maps[1].rsm.face_count == 1   # one exact face for a narrow spot
    assert methods[3] == "cm" and maps[3].rsm.face_count == 1   # the sun's orthographic map
    for index in (0, 2):
        assert methods[index] in ("wdpm", "twdpm")
        assert maps[index].rsm.face_count == (2 if index == 0 else 1)
    assert all(np.all(np.isfinite(image)) for image in frame.passes.values())


def test_a_sun_added_to_a_still_view_gets_its_cascade():
    """The grids' placement works a sun's cascade out only where the scene has a sun, and
    is placed again when one is added with the camera where it was."""
    from lpv_preview.gpu.scene import Light
    scene = room_scene(4)
    pipeline = Pipeline(Settings(width=32, height=32, rsm_resolution=64, vpls_per_light=128))
    try:
        pipeline.render(scene)
        assert pipeline._cascade_boxes == ()
        scene.lights = [*scene.lights, Light("SUN", (0, 0, 0), (0.3, 0.2, -1), (0, 1, 0), (1, 1, 1), 2.0)]
        frame = pipeline.render(scene)
        maps, _ = pipeline.light_maps(scene)
    finally:
        pipeline.release()
    assert pipeline._cascade_boxes and maps[-1].view_maps
    assert np.all(np.isfinite(frame.passes["direct"]))
