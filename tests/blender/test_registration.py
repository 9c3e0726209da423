"""The extension registers and unregisters cleanly, and its properties mirror gpu/settings.py."""
import pytest

bpy = pytest.importorskip("bpy")

import lpv_preview  # noqa: E402
from lpv_preview.addon import engine, ui  # noqa: E402
from lpv_preview.addon import overlay  # noqa: E402
from lpv_preview.operators import compare, presets  # noqa: E402
from lpv_preview.addon.properties import display_settings_from_properties, settings_from_properties  # noqa: E402
from lpv_preview.gpu.settings import ALL_PARAMETERS, DisplaySettings, Settings  # noqa: E402


def registered_state():
    """What the add-on can leave in Blender: classes, scene properties, engines listed in
    built-in panels, handlers and timers."""
    panels = [cls.__name__ for cls in ui.CLASSES if cls.is_registered]
    shared = [p.__name__ for p in engine.shared_panels() if engine.ENGINE_ID in p.COMPAT_ENGINES]
    handlers = {name: len(getattr(bpy.app.handlers, name)) for name in dir(bpy.app.handlers)
                if isinstance(getattr(bpy.app.handlers, name), list)}
    return {"scene property": hasattr(bpy.types.Scene, "lpv_preview"), "engine": engine.LPVPreviewEngine.is_registered,
            "panels": sorted(panels), "shared panels": len(shared) > 0, "handlers": handlers,
            "draw handlers": overlay.handler_count(),
            "operators": [cls.__name__ for cls in (*compare.CLASSES, presets.LPV_OT_apply_preset) if cls.is_registered]}


def test_register_unregister_three_times_leaves_nothing_behind():
    before = registered_state()
    assert not before["scene property"] and not before["engine"] and not before["panels"]
    assert before["draw handlers"] == 0
    for _ in range(3):
        lpv_preview.register()
        during = registered_state()
        assert during["scene property"] and during["engine"] and during["shared panels"]
        assert during["draw handlers"] == 2 and during["operators"] == ["LPV_OT_compare_with_cycles",
                                                                                   "LPV_OT_apply_preset"]
        assert len(during["panels"]) == len(ui.CLASSES)
        lpv_preview.unregister()
        assert registered_state() == before
        assert not hasattr(bpy.types, "LPVPreviewSettings")


def test_every_setting_has_its_place_in_the_panels():
    assert ui.check_groups()


def test_properties_mirror_the_settings():
    lpv_preview.register()
    scene = bpy.data.scenes.new("fresh")  # earlier tests may have changed the current scene's settings
    try:
        properties = scene.lpv_preview
        rna = properties.bl_rna.properties
        for name, field in ALL_PARAMETERS.items():
            assert rna[name].description == field.metadata["description"]
            if field.metadata["min"] is not None:
                assert rna[name].hard_min == pytest.approx(field.metadata["min"], rel=1e-6)
                assert rna[name].hard_max == pytest.approx(field.metadata["max"], rel=1e-6)
        assert settings_from_properties(properties) == Settings()
        assert display_settings_from_properties(properties) == DisplaySettings()
        properties.rsm_resolution = 256
        properties.lpv_slice_axis = "x"
        assert settings_from_properties(properties).rsm_resolution == 256
        assert display_settings_from_properties(properties).lpv_slice_axis == "x"
    finally:
        bpy.data.scenes.remove(scene)
        lpv_preview.unregister()
