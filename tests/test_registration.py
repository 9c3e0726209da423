"""The extension registers and unregisters cleanly, and its properties mirror gpu/settings.py."""
import pytest

bpy = pytest.importorskip("bpy")

import lpv_preview  # noqa: E402
from lpv_preview.addon.properties import settings_from_properties  # noqa: E402
from lpv_preview.gpu.settings import PARAMETERS, Settings  # noqa: E402


def test_register_unregister_three_times_leaves_nothing_behind():
    for _ in range(3):
        lpv_preview.register()
        assert hasattr(bpy.types.Scene, "lpv_preview")
        lpv_preview.unregister()
        assert not hasattr(bpy.types.Scene, "lpv_preview")
        assert not hasattr(bpy.types, "LPVPreviewSettings")


def test_properties_mirror_the_settings():
    lpv_preview.register()
    try:
        properties = bpy.context.scene.lpv_preview
        rna = properties.bl_rna.properties
        for name, field in PARAMETERS.items():
            assert rna[name].description == field.metadata["description"]
            if field.metadata["min"] is not None:
                assert rna[name].hard_min == pytest.approx(field.metadata["min"], rel=1e-6)
                assert rna[name].hard_max == pytest.approx(field.metadata["max"], rel=1e-6)
        assert settings_from_properties(properties) == Settings()
        properties.rsm_resolution = 256
        assert settings_from_properties(properties).rsm_resolution == 256
    finally:
        lpv_preview.unregister()
