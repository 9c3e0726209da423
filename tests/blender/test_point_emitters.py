"""Many emitters (issue 17, seed 002): emissive particles and instances read in bulk as
point emitters, the emitter grid against the brute-force loop, point lights beyond the
light-map budget, skipping what the view does not need, the emitters' bounce. Real GL
through llvmpipe, real bpy."""
import dataclasses

import numpy as np
import pytest

from lpv_preview.bench.synthetic import lamps_over_floor, particle_room
from lpv_preview.gpu.colour import LUMINANCE_WEIGHTS
from lpv_preview.gpu.context import GLContext
from lpv_preview.gpu.emitter_grid import EmitterGrid
from lpv_preview.gpu.frame_lights import frame_lights, light_bounds, skip_weak
from lpv_preview.gpu.errors import LPVError
from lpv_preview.gpu.metrics import psnr
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene import Scene
from lpv_preview.gpu.scene_file import load_scene, save_scene
from lpv_preview.gpu.settings import EMITTER_INTERPOLATIONS, Settings

SMALL = dict(width=80, height=60, emitter_grid_resolution=16, lpv_resolution=8, rsm_resolution=64,
             vpls_per_light=256, emitter_bounce_samples=256)


@pytest.fixture(scope="module")
def particles():
    return particle_room(2000)


def test_grid_matches_brute_force(particles):
    """Each interpolation of a 16³ grid stays within 35 dB of every pixel summing every emitter."""
    pipeline = Pipeline(Settings(**SMALL))
    try:
        reference = pipeline.render(particles, Settings(**SMALL, emitter_light="brute_force"),
                                    passes=("direct",)).passes["direct"]
        for interpolation in EMITTER_INTERPOLATIONS:
            frame = pipeline.render(particles, Settings(**SMALL, emitter_interpolation=interpolation),
                                    passes=("direct", "indirect"))
            assert psnr(frame.passes["direct"], reference) >= 35.0, interpolation
            assert frame.stats["point_emitters"] + frame.stats["skipped_emitters"] == 2000
    finally:
        pipeline.release()
    assert reference.mean() > 0


def test_emitters_light_the_room_and_it_bounces(particles):
    """A room lit only by particles gets direct light on every wall the camera sees, but
    where a particle covers the pixel (it shows the particle's glow), and bounce light from
    them; an unchanged frame builds no grid again."""
    pipeline = Pipeline(Settings(**SMALL))
    try:
        frame = pipeline.render(particles, passes=("direct", "indirect", "combined"))
        grid = pipeline.last_emitter_grid
        built = grid._built
        pipeline.render(particles, passes=("direct",))
        assert pipeline.last_emitter_grid is grid and grid._built is built
    finally:
        pipeline.release()
    direct, indirect = frame.passes["direct"], frame.passes["indirect"]
    covered = direct.mean(axis=2) <= 0  # measured: 1 pixel of 4,800
    assert covered.mean() < 0.01 and np.all(frame.passes["combined"][covered].mean(axis=-1) > 0)
    assert 0.05 * direct.mean() < indirect.mean() < direct.mean()  # albedo 0.6 in a closed room


def test_light_map_budget_and_weak_lights():
    """Of 64 lamps the 3 strongest get maps and the other 61 light through the grid; a
    lamp a kilometre away is skipped, and the frame is the same without it."""
    scene = lamps_over_floor(64)
    far = lamps_over_floor(1).lights[0]
    far.position = np.array([1000.0, 0.0, 1.0])
    with_far = Scene(scene.triangles, scene.normals, scene.albedo, scene.lights + [far], scene.camera).sanitize()
    pipeline = Pipeline(Settings(**SMALL))
    try:
        frame = pipeline.render(with_far, passes=("combined",))
        assert (frame.stats["mapped_lights"], frame.stats["lights_as_emitters"], frame.stats["skipped_lights"]) == \
            (3, 61, 1)
        everything = pipeline.render(with_far, Settings(**SMALL, light_cutoff=0.0), passes=("combined",))
        assert everything.stats["skipped_lights"] == 0
    finally:
        pipeline.release()
    assert psnr(frame.passes["combined"], everything.passes["combined"]) > 40.0


def test_skip_weak_bounds_what_it_drops():
    rng = np.random.default_rng(3)
    positions = rng.uniform(-100, 100, (5000, 3))
    intensity = rng.uniform(0, 1, 5000)
    box = (np.array([-1.0, -1, -1]), np.array([1.0, 1, 1]))
    bound = light_bounds(positions, intensity, box, 0.1)
    gap = np.maximum(np.maximum(box[0] - positions, positions - box[1]), 0)
    assert np.allclose(bound, intensity / np.maximum((gap ** 2).sum(axis=1), 0.01), rtol=1e-5)
    keep = skip_weak(bound, 0.01)
    assert 0 < (~keep).sum() < 5000
    assert bound[~keep].sum() <= 0.01 * bound.sum()
    assert bound[~keep].max() <= bound[keep].min()


def test_a_frames_emitters_are_the_kept_ones_with_their_flux_and_box():
    """The GPU skips the emitters weakest at the view by the lamps' rule (skip_weak): the
    skipped ones leave the frame's emitters, its flux bound and its box."""
    scene = particle_room(2000)
    far = np.array([[500.0 + i, -400.0, 300.0, 1e-6, 1e-6, 1e-6, 1e-4] for i in range(50)], np.float32)
    scene = dataclasses.replace(scene, point_emitters=np.concatenate([scene.point_emitters, far]))
    scene.sanitize()
    box = scene.bounds()
    rows = scene.point_emitters
    bound = light_bounds(rows[:, :3], rows[:, 3:6] @ LUMINANCE_WEIGHTS.astype(np.float32) / np.float32(4 * np.pi), box,
                         0.1)
    expected = skip_weak(bound, 0.01)
    glc = GLContext.shared()
    grid = EmitterGrid(glc, 8)
    try:
        grid.upload(rows, None, "far")
        selection = grid.select(box, 0.1, 0.01)
        kept = np.frombuffer(grid.emitters.read(), np.float32).reshape(-1, 12)[:len(rows), 3] > 0
    finally:
        grid.release()
    assert selection.skipped >= len(far) and not kept[-len(far):].any()
    assert selection.kept == kept.sum() == len(rows) - selection.skipped
    assert abs(int(kept.sum()) - int(expected.sum())) <= 0.01 * len(rows)  # bins of other widths than skip_weak's
    assert bound[~kept].sum() <= 0.01 * bound.sum()
    np.testing.assert_allclose(selection.box[0], rows[kept, :3].min(axis=0))
    np.testing.assert_allclose(selection.box[1], rows[kept, :3].max(axis=0))
    assert selection.flux_bound == pytest.approx(rows[kept, 3:6].sum(axis=0, dtype=np.float64).max(), rel=1e-4)


def _trilinear(texels, g):
    """numpy's trilinear read of (z, y, x, 4) texels at points `g` (x, y, z in texels, centres
    at i + 0.5), clamped at the edges as the grid's textures are."""
    size = texels.shape[0]
    at = g - 0.5
    low = np.floor(at).astype(int)
    f = at - low
    total = 0.0
    for corner in np.ndindex(2, 2, 2):
        weight = np.prod(np.where(np.array(corner), f, 1.0 - f), axis=1)[:, None]
        x, y, z = np.clip(low + np.array(corner), 0, size - 1).T
        total = total + weight * texels[z, y, x]
    return total


def test_the_super_sampled_read_is_one_read_of_textures_twice_as_fine(particles):
    """The mean of eight trilinear reads a quarter cell around a point (the seed's super-
    sampling) equals one trilinear read of the textures shaders/emitter_supersample.comp
    makes twice as fine, inside the grid and beyond its edges."""
    glc = GLContext.shared()
    grid = EmitterGrid(glc, 8)
    try:
        grid.upload(particles.point_emitters, None, "supersampled")
        grid.select(particles.bounds(), 0.1, 0.0)
        grid.build(particles.bounds(), 100.0)
        fine = grid.supersampled_textures()
        n = grid.resolution
        coarse = [np.frombuffer(t.read(), np.float32).reshape(n, n, n, 4) for t in grid.textures]
        fine = [np.frombuffer(t.read(), np.float32).reshape(2 * n, 2 * n, 2 * n, 4) for t in fine]
    finally:
        grid.release()
    g = np.random.default_rng(3).uniform(-0.5, n + 0.5, (500, 3))
    offsets = 0.25 * (np.array(list(np.ndindex(2, 2, 2))) * 2 - 1)
    for coarse_texels, fine_texels in zip(coarse, fine):
        mean = sum(_trilinear(coarse_texels, g + offset) for offset in offsets) / 8
        assert np.abs(coarse_texels).max() > 0
        np.testing.assert_allclose(_trilinear(fine_texels, 2 * g), mean, rtol=1e-5,
                                   atol=1e-6 * np.abs(coarse_texels).max())


def test_lamps_beyond_the_budget_are_kept_emitters():
    """Point lights beyond the map budget join the scene's emitters and are never skipped."""
    scene = lamps_over_floor(8)
    lit = frame_lights(scene, Settings(light_map_budget=3), scene.bounds(), 0.1)
    assert len(lit.mapped) == 3 and lit.lamp_rows.shape == (5, 7)
    grid = EmitterGrid(GLContext.shared(), 8)
    try:
        grid.upload(None, lit.lamp_rows, lit.key)
        selection = grid.select(scene.bounds(), 0.1, 0.5)
    finally:
        grid.release()
    assert (selection.kept, selection.skipped) == (5, 0)


def test_point_emitters_are_checked_and_saved(tmp_path, particles):
    """Rows with NaN, negative or no flux are dropped and counted in the frame's
    statistics; a scene file keeps its rows."""
    rows = np.array([[0, 0, 1, 1, 1, 1, 0.01], [np.nan, 0, 1, 1, 1, 1, 0.01], [0, 0, 1, -1, 1, 1, 0.01],
                     [0, 0, 1, 0, 0, 0, 0.01]])
    scene = Scene(particles.triangles, particles.normals, particles.albedo, [], particles.camera,
                  point_emitters=rows).sanitize()
    pipeline = Pipeline(Settings(**SMALL))
    try:
        frame = pipeline.render(scene, passes=("combined",))
    finally:
        pipeline.release()
    assert frame.stats["point_emitters"] == 1 and frame.stats["dropped_triangles"]["emitters"] == 3
    assert np.isfinite(frame.passes["combined"]).all() and frame.passes["combined"].max() > 0
    unlit = Scene(particles.triangles, particles.normals, particles.albedo, [], particles.camera,
                  point_emitters=rows[1:]).sanitize()  # every row bad, and nothing else lights it
    pipeline = Pipeline(Settings(**SMALL))
    try:
        with pytest.raises(LPVError, match="no lights"):
            pipeline.render(unlit, passes=("combined",))
    finally:
        pipeline.release()
    save_scene(particles, tmp_path / "particles.npz")
    loaded = load_scene(tmp_path / "particles.npz")
    assert np.array_equal(loaded.point_emitters, particles.point_emitters)


def test_emissive_instances_and_particles_become_point_emitters():
    """Geometry-node instances and a particle system of an emissive sphere are read in
    bulk as one point emitter each, with the sphere's flux, and drawn as no triangles;
    a few copies stay meshes."""
    bpy = pytest.importorskip("bpy")
    from lpv_preview.addon.extract import extract_scene
    from lpv_preview.addon.point_emitters import BULK_INSTANCES
    from lpv_preview.demo.particles import instance_on_points

    from ..leak_scenes import camera, diffuse, empty_scene, light, quad
    empty_scene((32, 24))
    quad("Floor", 3.0, 0.0, diffuse("Grey", (0.8, 0.8, 0.8)))
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=1, radius=0.02, location=(0, 0, 40))
    sphere = bpy.context.object
    glow = bpy.data.materials.new("Glow")
    principled = glow.node_tree.nodes["Principled BSDF"]
    principled.inputs["Emission Color"].default_value = (1.0, 0.5, 0.25, 1.0)
    principled.inputs["Emission Strength"].default_value = 10.0
    sphere.data.materials.append(glow)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=9, y_subdivisions=9, size=2, location=(0, 0, 1))
    bpy.context.object.modifiers.new("Scatter", "NODES").node_group = instance_on_points(sphere)
    bpy.ops.mesh.primitive_plane_add(size=2, location=(0, 0, 0.5))
    emitter = bpy.context.object
    emitter.modifiers.new("Sparks", "PARTICLE_SYSTEM")
    sparks = emitter.particle_systems[0].settings
    sparks.count, sparks.frame_start, sparks.frame_end, sparks.lifetime = 70, 1, 1, 100
    sparks.render_type, sparks.instance_object, sparks.particle_size = "OBJECT", sphere, 2.0
    light("POINT", (0, 0, 3), energy=10.0)
    camera("Camera", (0, -5, 3), (0, 0, 0))
    bpy.context.scene.frame_set(3)
    scene = extract_scene(bpy.context.evaluated_depsgraph_get())
    assert BULK_INSTANCES <= 70 and scene.point_emitter_count == 100 + 70
    areas = np.empty(len(sphere.data.polygons))
    sphere.data.polygons.foreach_get("area", areas)
    one = np.pi * np.array([1.0, 0.5, 0.25]) * 10.0 * areas.sum()
    flux = scene.point_emitters[:, 3:6]
    assert np.allclose(flux[:100], one, rtol=1e-4) and np.allclose(flux[100:], 4 * one, rtol=1e-4)
    assert scene.triangle_count == 2 + 2 + 20  # floor, particle plane and the sphere itself: no copy drawn
    assert np.allclose(scene.point_emitters[:100, 2], 1.0, atol=1e-5)


def test_collection_instances_become_point_emitters():
    """Geometry nodes placing a collection that holds an emissive sphere and a plain cube:
    one point emitter per copy of the sphere, where the collection puts it."""
    bpy = pytest.importorskip("bpy")
    from lpv_preview.addon.extract import extract_scene
    from lpv_preview.demo.particles import instance_on_points

    from ..leak_scenes import camera, diffuse, empty_scene, light, quad
    empty_scene((32, 24))
    quad("Floor", 3.0, 0.0, diffuse("Grey", (0.8, 0.8, 0.8)))
    lantern = bpy.data.collections.new("Lantern")
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=1, radius=0.05, location=(0, 0, 0.5))
    sphere = bpy.context.object
    glow = bpy.data.materials.new("Glow")
    glow.node_tree.nodes["Principled BSDF"].inputs["Emission Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    glow.node_tree.nodes["Principled BSDF"].inputs["Emission Strength"].default_value = 5.0
    sphere.data.materials.append(glow)
    bpy.ops.mesh.primitive_cube_add(size=0.1, location=(0, 0, 0))
    post = bpy.context.object
    for member in (sphere, post):
        for owner in member.users_collection:
            owner.objects.unlink(member)
        lantern.objects.link(member)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=8, y_subdivisions=8, size=2, location=(0, 0, 0))
    bpy.context.object.modifiers.new("Lanterns", "NODES").node_group = instance_on_points(lantern)
    light("POINT", (0, 0, 3), energy=10.0)
    camera("Camera", (0, -5, 3), (0, 0, 0))
    scene = extract_scene(bpy.context.evaluated_depsgraph_get())
    assert scene.point_emitter_count == 81  # a grid of 8 × 8 quads has 9 × 9 points
    assert np.allclose(scene.point_emitters[:, 2], 0.5, atol=1e-5)  # the sphere's place in the collection
    assert scene.triangle_count == 2 + 81 * 12  # the floor and every cube; no sphere


@pytest.mark.parametrize("scale", [1e-3, 1e4])
def test_the_emitters_light_the_same_at_any_scale(scale):
    """The particle room a thousand times smaller or ten thousand times larger (flux by
    scale², the same irradiance): brute force gives the same image, and the grid stays as
    close to it as at 1 m (where its cells, and the shadows' cells, fall against the scene
    moves with the scale)."""
    pipeline = Pipeline(Settings(**SMALL))
    try:
        images = {(s, light): pipeline.render(particle_room(500, scale=s),
                                              Settings(**SMALL, emitter_light=light, emitter_shadows=False),
                                              passes=("direct",)).passes["direct"]
                  for s in (1.0, scale) for light in ("grid", "brute_force")}
        shaded = [pipeline.render(particle_room(500, scale=s), Settings(**SMALL), passes=("direct",)).passes["direct"]
                  for s in (1.0, scale)]
    finally:
        pipeline.release()
    assert psnr(images[scale, "brute_force"], images[1.0, "brute_force"]) > 60.0
    assert psnr(images[scale, "grid"], images[scale, "brute_force"]) > 25.0
    assert abs(images[scale, "grid"].mean() / images[1.0, "grid"].mean() - 1) < 0.02
    assert abs(shaded[1].mean() / shaded[0].mean() - 1) < 0.02


def test_a_particle_glows_with_its_own_light():
    """The camera sees a particle as a disc of its radiance: its image, summed over the
    pixels' solid angles, is the irradiance it gives the camera, Φ / (4π d²)."""
    room = particle_room(1)
    camera = room.camera
    forward = -np.linalg.inv(camera.view)[:3, 2]
    place = camera.position + 1.5 * forward
    flux = np.array([3.0, 2.0, 1.0])
    settings = Settings(**SMALL)
    pixel_angle = 2.0 / (camera.projection[1, 1] * settings.height)
    wide = 4 * np.pi * (8 * 1.5 * pixel_angle) ** 2  # a disc 8 pixels in radius: its workgroup adds it
    for area in (1e-6, 4e-4, wide):  # a speck, a disc a few pixels wide and a wide one
        emitters = np.array([[*place, *flux, area]])
        scene = Scene(room.triangles, room.normals, room.albedo, [], camera, point_emitters=emitters).sanitize()
        pipeline = Pipeline(settings)
        try:
            frame = pipeline.render(scene, passes=("combined", "direct", "indirect"))
        finally:
            pipeline.release()
        glow = frame.passes["combined"] - frame.passes["direct"] - frame.passes["indirect"]
        seen = glow.reshape(-1, 3).sum(axis=0) * pixel_angle ** 2
        assert np.allclose(seen, flux / (4 * np.pi * 1.5 ** 2), rtol=0.1), area


def test_a_particle_behind_a_wall_does_not_glow():
    """The G-buffer's depth hides a speck (added into its pixel by a compute pass) and a
    disc (drawn) behind the room's far wall alike."""
    room = particle_room(1)
    camera = room.camera
    forward = -np.linalg.inv(camera.view)[:3, 2]
    for area in (1e-6, 4.0):
        emitters = np.array([[*(camera.position + 5.0 * forward), 3.0, 2.0, 1.0, area]])
        scene = Scene(room.triangles, room.normals, room.albedo, [], camera, point_emitters=emitters).sanitize()
        pipeline = Pipeline(Settings(**SMALL))
        try:
            frame = pipeline.render(scene, passes=("combined", "direct", "indirect"))
        finally:
            pipeline.release()
        glow = frame.passes["combined"] - frame.passes["direct"] - frame.passes["indirect"]
        assert np.abs(glow).max() < 1e-6 * frame.passes["combined"].max(), area


@pytest.mark.parametrize("method", ["light_grid", "vpl_gather"])
def test_a_lamp_bounces_alike_through_its_maps_and_as_an_emitter(method):
    """One lamp in the closed room: with a map its VPLs come from the map; beyond the
    budget it is a point emitter whose light reaches surface points that become VPLs.
    The two indirect images agree within 10 % on average."""
    scene = lamps_over_floor(1)
    means = []
    for budget in (1, 0):
        settings = Settings(**{**SMALL, "vpls_per_light": 2048, "emitter_bounce_samples": 2048, "lpv_resolution": 16},
                            indirect_method=method, light_map_budget=budget, emitter_shadows=False,
                            bounces=1)  # the first bounce: through the map's VPLs or the surface points
        pipeline = Pipeline(settings)
        try:
            frame = pipeline.render(scene, passes=("indirect",))
        finally:
            pipeline.release()
        assert frame.stats["lights_as_emitters"] == 1 - budget
        means.append(frame.passes["indirect"].mean())
    assert abs(means[1] / means[0] - 1) < 0.1


def test_what_moves_is_redrawn(particles):
    """Particles that move change the direct light; a wall that moves in a room lit only
    by particles changes the bounce light (the stages' keys hold emitters and geometry)."""
    moved = np.array(particles.point_emitters)
    moved[:, 0] += 0.3
    shifted = Scene(particles.triangles, particles.normals, particles.albedo, [], particles.camera,
                    point_emitters=moved).sanitize()
    floor = particles.triangles[:, :, 2].max(axis=1) < 0.01
    raised = np.array(particles.triangles)
    raised[floor, :, 2] += 0.5
    lifted = Scene(raised, particles.normals, particles.albedo, [], particles.camera,
                   point_emitters=particles.point_emitters).sanitize()
    pipeline = Pipeline(Settings(**SMALL))
    try:
        first = pipeline.render(particles, passes=("direct", "indirect")).passes
        after_move = pipeline.render(shifted, passes=("direct",)).passes["direct"]
        after_lift = pipeline.render(lifted, passes=("indirect",)).passes["indirect"]
    finally:
        pipeline.release()
    assert np.abs(after_move - first["direct"]).mean() > 0.02 * first["direct"].mean()
    assert np.abs(after_lift - first["indirect"]).mean() > 0.02 * first["indirect"].mean()


@pytest.mark.parametrize("method", ["lpv", "vpl_gather"])
def test_particles_bounce_with_every_indirect_method(particles, method):
    pipeline = Pipeline(Settings(**SMALL, indirect_method=method))
    try:
        frame = pipeline.render(particles, passes=("direct", "indirect"))
    finally:
        pipeline.release()
    assert 0.05 * frame.passes["direct"].mean() < frame.passes["indirect"].mean() < frame.passes["direct"].mean()


def test_lamps_with_no_map_budget_and_specks_without_area_render():
    """A budget of 0 sends every lamp through the grid; emitters of no area render finite."""
    lamps = lamps_over_floor(8)
    room = particle_room(50)
    specks = np.array(room.point_emitters)
    specks[:, 6] = 0.0
    tiny = Scene(room.triangles, room.normals, room.albedo, [], room.camera, point_emitters=specks).sanitize()
    pipeline = Pipeline(Settings(**SMALL, light_map_budget=0))
    try:
        for scene, lights_as_emitters in ((lamps, 8), (tiny, 0)):
            frame = pipeline.render(scene, passes=("combined",))
            assert np.isfinite(frame.passes["combined"]).all() and frame.passes["combined"].mean() > 0
            assert (frame.stats["mapped_lights"], frame.stats["lights_as_emitters"]) == (0, lights_as_emitters)
    finally:
        pipeline.release()


def test_a_malformed_emitter_array_is_refused_in_one_sentence(particles):
    with pytest.raises(LPVError, match=r"point emitters are an array of shape \(10, 6\); give one row of 7 numbers"):
        Scene(particles.triangles, particles.normals, particles.albedo, [], particles.camera,
              point_emitters=np.ones((10, 6))).sanitize()


def test_particles_that_move_start_a_still_frame_again(particles):
    """A converging frame averages VPL sets while nothing changes; particles that move
    are a change."""
    moved = np.array(particles.point_emitters)
    moved[:, 2] += 0.1
    shifted = Scene(particles.triangles, particles.normals, particles.albedo, [], particles.camera,
                    point_emitters=moved).sanitize()
    pipeline = Pipeline(Settings(**SMALL))
    try:
        pipeline.render(particles, passes=(), vpl_set=0, accumulate=True)
        assert pipeline.render(particles, passes=(), vpl_set=1, accumulate=True).stats["vpl_sets"] == 2
        assert pipeline.render(shifted, passes=(), vpl_set=2, accumulate=True).stats["vpl_sets"] == 1
    finally:
        pipeline.release()


def test_moving_particles_are_read_alone_and_move():
    """An instancer whose instances are all point emitters and that draws nothing itself,
    moved, is read again alone (addon/sync.py EMITTERS: no walk over its instances): its
    point emitters move with it, the triangles are the same arrays, and the rows are those
    a whole read gives."""
    bpy = pytest.importorskip("bpy")
    from lpv_preview.addon.extract import extract_camera
    from lpv_preview.addon.sync import EMITTERS, SceneSync, changed_parts
    from lpv_preview.demo import particles as particle_demo

    from ..depsgraph_updates import recorded_updates
    bpy.ops.wm.read_factory_settings(use_empty=True)
    particle_demo.build(particles=200)
    swirl = bpy.data.objects["Swirl"]
    sync = SceneSync()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    camera = extract_camera(depsgraph, (32, 24))
    first = sync.scene(depsgraph, set(), camera)
    assert sync.emitters_alone == {swirl.as_pointer()}
    records = recorded_updates(lambda: setattr(swirl.location, "z", swirl.location.z + 0.25))
    parts = changed_parts(records, sync.emitters_alone)
    assert parts == {EMITTERS}, records
    depsgraph = bpy.context.evaluated_depsgraph_get()
    moved = sync.scene(depsgraph, parts, camera)
    assert sync.extracted == (EMITTERS,) and moved.triangles is first.triangles
    np.testing.assert_allclose(moved.point_emitters[:, 2], first.point_emitters[:, 2] + 0.25, atol=1e-5)
    np.testing.assert_array_equal(moved.point_emitters[:, 3:], first.point_emitters[:, 3:])
    whole = SceneSync().scene(depsgraph, set(), camera)
    np.testing.assert_allclose(moved.point_emitters, whole.point_emitters, atol=1e-5)
