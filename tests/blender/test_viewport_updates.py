"""The viewport's update logic: real depsgraph updates, recorded from real edits, decide
what is extracted again, and the pipeline reruns exactly the stages docs/architecture.md lists."""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

import lpv_preview  # noqa: E402
from lpv_preview import demo  # noqa: E402
from lpv_preview.addon.viewport import ViewportSession  # noqa: E402
from lpv_preview.addon.extract import extract_camera  # noqa: E402
from lpv_preview.addon.sync import CAMERA, EMITTERS, EVERYTHING, GEOMETRY, LIGHTS, changed_parts  # noqa: E402
from lpv_preview.gpu.indirect import INDIRECT_STAGES  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

from ..depsgraph_updates import recorded_updates  # noqa: E402

LIGHT_STAGES = ("rsm_ms", "vpl_ms")
INDIRECT_STAGES_NOW = INDIRECT_STAGES[Settings().indirect_method]
SHADING_STAGES = ("direct_ms", "indirect_ms")
CAMERA_STAGES = ("gbuffer_ms",) + SHADING_STAGES


@pytest.fixture(scope="module")
def registered():
    """The add-on registered: a session reads the scene's properties."""
    lpv_preview.register()
    yield
    lpv_preview.unregister()


@pytest.fixture(scope="module")
def cornell_scene(registered):
    """The Cornell box with small settings."""
    scene = demo.build("cornell")
    settings = scene.lpv_preview
    settings.rsm_resolution, settings.vpls_per_light, settings.lpv_resolution = 64, 256, 16
    return scene


@pytest.fixture(scope="module")
def session(cornell_scene):
    session = ViewportSession()
    yield session
    session.release()


def frame(session):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    return session.frame(depsgraph, extract_camera(depsgraph, (48, 48)), (48, 48))


def move_camera():
    bpy.context.scene.camera.location.x += 0.05


def move_light():
    next(o for o in bpy.context.scene.objects if o.type == "LIGHT").location.x += 0.05


def edit_mesh():
    mesh = next(o for o in bpy.context.scene.objects if o.type == "MESH").data
    mesh.vertices[0].co.z += 0.01
    mesh.update()


def edit_material():
    material = next(m for m in bpy.data.materials if m.users and m.node_tree)
    principled = next(n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    colour = principled.inputs["Base Color"].default_value
    colour[0] = 0.5 * colour[0] + 0.1


@pytest.mark.parametrize("edit, parts, extracted, reruns, reused", [
    (move_camera, {CAMERA}, [], CAMERA_STAGES, LIGHT_STAGES + INDIRECT_STAGES_NOW),
    (move_light, {LIGHTS}, [LIGHTS], LIGHT_STAGES + INDIRECT_STAGES_NOW + SHADING_STAGES, ()),
    (edit_mesh, {GEOMETRY}, [GEOMETRY], LIGHT_STAGES + INDIRECT_STAGES_NOW + CAMERA_STAGES, ()),
    (edit_material, {GEOMETRY}, [GEOMETRY], LIGHT_STAGES + INDIRECT_STAGES_NOW + CAMERA_STAGES, ()),
], ids=["camera", "light", "mesh", "material"])
def test_an_edit_reruns_exactly_the_stages_that_depend_on_it(session, edit, parts, extracted, reruns, reused):
    first = frame(session)  # settle: whatever was pending is done
    assert set(first.stats) >= set(SHADING_STAGES)
    records = recorded_updates(edit)
    assert changed_parts(records) == parts, records
    session.note_updates(records)
    after = frame(session)
    assert after.stats["extracted"] == extracted
    assert all(stage in after.stats for stage in reruns), after.stats
    assert not any(stage in after.stats for stage in reused), after.stats


def test_a_dragged_light_keeps_the_view_s_g_buffer(session):
    """Each step of a light's drag restarts the VPL sets at the pixels' centres: the step
    after the first draws the same view of the same surfaces and keeps its G-buffer."""
    frame(session)
    for step in range(2):
        session.note_updates(recorded_updates(move_light))
        after = frame(session)
    assert all(stage in after.stats for stage in LIGHT_STAGES + SHADING_STAGES), after.stats
    assert "gbuffer_ms" not in after.stats


def test_the_first_frame_reads_everything_and_an_idle_redraw_nothing(cornell_scene):
    session = ViewportSession()
    try:
        assert session.pending == set(EVERYTHING)
        assert frame(session).stats["extracted"] == [GEOMETRY, LIGHTS]
        again = frame(session)
        assert again.stats["extracted"] == []
        assert not any(stage in again.stats for stage in LIGHT_STAGES + INDIRECT_STAGES_NOW)
    finally:
        session.release()


def test_a_redraw_with_nothing_changed_shows_the_last_frame_again(cornell_scene):
    cornell_scene.lpv_preview.viewport_vpl_sets = 1
    session = ViewportSession()
    try:
        depsgraph = bpy.context.evaluated_depsgraph_get()
        camera = extract_camera(depsgraph, (48, 48))
        first = session.frame_to_draw(depsgraph, camera, (48, 48))
        assert session.frame_to_draw(depsgraph, camera, (48, 48)) is first
        assert session.frame_to_draw(depsgraph, camera, (40, 48)) is not first  # the region was resized
        records = recorded_updates(move_camera)
        session.note_updates(records)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        moved = session.frame_to_draw(depsgraph, extract_camera(depsgraph, (48, 48)), (48, 48))
        assert moved is not first and all(stage in moved.stats for stage in CAMERA_STAGES)
    finally:
        cornell_scene.lpv_preview.property_unset("viewport_vpl_sets")
        session.release()


def test_a_still_view_converges_at_finer_grids_a_move_keeps_them_and_an_edit_starts_again(cornell_scene):
    cornell_scene.lpv_preview.viewport_vpl_sets = 3
    cornell_scene.lpv_preview.converged_lpv_resolution = 20  # automatic keeps 16³ on llvmpipe; 20³ gathers fast
    session = ViewportSession()
    try:
        def draw():
            depsgraph = bpy.context.evaluated_depsgraph_get()
            return session.frame_to_draw(depsgraph, extract_camera(depsgraph, (48, 48)), (48, 48))

        frames = [draw() for _ in range(4)]
        # The first frame at the scene's 16³, then the average starts again at the finer grids.
        assert [(f.stats["vpl_sets"], f.stats["lpv_resolution"]) for f in frames] == [(1, 16), (1, 20), (2, 20),
                                                                                    (3, 20)]
        assert not session.converging(session_display(cornell_scene))
        last = draw()
        assert last is frames[-1] and last.stats["accumulated_vpls"] == 3 * last.stats["vpl_count"]
        session.note_updates(recorded_updates(move_camera))
        moved = draw()  # keeps the finer grids, which still fit: nothing on the light side is made again
        assert moved.stats["vpl_sets"] == 1 and moved.stats["lpv_resolution"] == 20
        assert session.converging(session_display(cornell_scene))
        assert not any(stage in moved.stats for stage in ("rsm_ms", "vpl_ms", "inject_ms", "gather_ms"))
        session.note_updates(recorded_updates(move_light))
        lit = draw()  # an edit goes back to the coarser grids, for speed
        assert lit.stats["vpl_sets"] == 1 and lit.stats["lpv_resolution"] == 16
        assert draw().stats["lpv_resolution"] == 20  # still again: refined again
        cornell_scene.lpv_preview.vpls_per_light = 128  # an edit in the panel
        assert draw().stats["lpv_resolution"] == 16
    finally:
        cornell_scene.lpv_preview.property_unset("viewport_vpl_sets")
        cornell_scene.lpv_preview.property_unset("converged_lpv_resolution")
        cornell_scene.lpv_preview.vpls_per_light = 256
        session.release()


def session_display(scene):
    from lpv_preview.addon.properties import display_settings_from_properties
    return display_settings_from_properties(scene.lpv_preview)


def test_the_viewport_reads_the_combined_image_bottom_row_first_into_its_own_buffer(session):
    drawn = frame(session)
    assert np.shares_memory(drawn.display, session.display.rows)
    assert drawn.display.shape == (48, 48, 3) and session.display.fresh
    depsgraph = bpy.context.evaluated_depsgraph_get()
    scene = session.sync.scene(depsgraph, set(), extract_camera(depsgraph, (48, 48)))
    alone = session.gl.call(session.pipeline.render, scene, passes=("combined",)).passes["combined"]  # its thread
    assert alone.mean() > 0
    np.testing.assert_array_equal(drawn.display[::-1], alone)


def test_overlay_data_follows_the_light_side_and_the_overlay_settings(cornell_scene):
    properties = cornell_scene.lpv_preview
    properties.viewport_vpl_sets = 1  # a still view's new VPL sets would change the VPLs shown
    session = ViewportSession()
    try:
        def draw():
            depsgraph = bpy.context.evaluated_depsgraph_get()
            session.note_updates([])
            return session.frame_to_draw(depsgraph, extract_camera(depsgraph, (48, 48)), (48, 48))

        drawn = draw()
        assert session.overlays.empty
        properties.method, properties.show_vpls, properties.show_lpv_slice, properties.show_warp_status = (
            "wdpm", True, True, True)
        drawn = draw()
        overlays = session.overlays
        invalid = session.gl.call(lambda: sum(int((~vpls.read()["valid"]).sum())
                                              for vpls in session.pipeline.last_light_maps[0].vpl_sets()))
        assert len(overlays.vpls.positions) == drawn.stats["vpl_count"] - invalid
        assert overlays.slice.image.shape == (16, 16, 4) and overlays.slice.light.sum() > 0
        assert overlays.warp_status.shape[:2] == session.pipeline.last_light_maps[0].warp.texture.size[::-1]
        shown = (overlays.vpls, overlays.slice, overlays.warp_status)
        session.note_updates(recorded_updates(move_camera))
        draw()  # a camera move keeps the LPV, so the overlays keep their data
        assert (overlays.vpls, overlays.slice, overlays.warp_status) == shown
        properties.lpv_slice_axis = "x"
        draw()
        assert overlays.slice is not shown[1] and overlays.vpls is shown[0]
        session.note_updates(recorded_updates(move_light))
        draw()
        assert overlays.vpls is not shown[0]
        properties.show_vpls = properties.show_lpv_slice = properties.show_warp_status = False
        draw()
        assert overlays.empty
    finally:
        properties.method, properties.lpv_slice_axis = "cm", "z"
        properties.show_vpls = properties.show_lpv_slice = properties.show_warp_status = False
        properties.property_unset("viewport_vpl_sets")
        session.release()


def test_painting_an_image_reaches_the_next_frame(registered):
    """An image edit that tags the image is a geometry update: the next frame reads the new
    pixels and the camera sees them."""
    from .test_textures import checker_image, floor_scene, image_material
    scene, _ = floor_scene(lambda: image_material(checker_image()))
    session = ViewportSession()
    try:
        depsgraph = bpy.context.evaluated_depsgraph_get()
        camera = extract_camera(depsgraph, (48, 48))
        before = session.frame(depsgraph, camera, (48, 48), settings=small_settings()).display.copy()

        def paint():
            image = bpy.data.images["Checker"]
            image.pixels.foreach_set(np.full(len(image.pixels), 1.0, dtype=np.float32))
            image.update()
            image.update_tag()  # a tagged image reaches the depsgraph as an IMAGE update

        records = recorded_updates(paint)
        assert GEOMETRY in changed_parts(records), records
        session.note_updates(records)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        after = session.frame(depsgraph, camera, (48, 48), settings=small_settings())
        assert after.stats["extracted"] == [GEOMETRY]
        assert after.display[16:32, 16:32, 0].min() > before[16:32, 16:32, 0].min() * 5  # the dark squares are white
    finally:
        session.release()


def test_moving_particles_redraw_their_light_alone(registered):
    """An instancer whose instances are all point emitters, moved, is read again alone
    (EMITTERS): the next frame keeps the G-buffer, and the particles' light moves with them."""
    demo.build("particles", particles=300, resolution=(48, 48))
    swirl = bpy.data.objects["Swirl"]
    session = ViewportSession()
    try:
        depsgraph = bpy.context.evaluated_depsgraph_get()
        camera = extract_camera(depsgraph, (48, 48))
        before = session.frame(depsgraph, camera, (48, 48), settings=small_settings()).display.copy()
        records = recorded_updates(lambda: setattr(swirl.location, "x", swirl.location.x + 0.8))
        assert changed_parts(records, session.sync.emitters_alone) == {EMITTERS}, records
        session.note_updates(records)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        after = session.frame(depsgraph, camera, (48, 48), settings=small_settings())
        assert after.stats["extracted"] == [EMITTERS]
        assert "gbuffer_ms" not in after.stats and "emitter_select_ms" in after.stats
        right = np.s_[:, 24:, 0]  # the swirl moved toward +x: the right half of the view is lit more
        assert after.display[right].mean() > 1.05 * before[right].mean()
    finally:
        session.release()


def small_settings():
    from lpv_preview.gpu.settings import Settings
    return Settings(width=48, height=48, rsm_resolution=64, vpls_per_light=128, lpv_resolution=8)
