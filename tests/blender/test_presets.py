"""The presets of gpu/settings.py: valid, distinct and ordered, applied by the panel's
operator, by --preset on the command line (flags given win) and as a sweep axis."""
import json
from pathlib import Path

import pytest

from lpv_preview.cli.flags import settings_from
from lpv_preview.cli.parser import build_parser
from lpv_preview.gpu.errors import LPVError
from lpv_preview.gpu.settings import (PRESET_PARAMETERS, PRESETS, Settings, describe_preset, matching_preset,
                                      preset_settings)
from lpv_preview.bench.sweep import load_sweep, sweep_points
from lpv_preview.bench.sweep_report import choose_presets


def test_presets_are_valid_distinct_and_ordered_by_cost():
    assert list(PRESETS) == ["fast", "balanced", "accurate"]
    chosen = [preset_settings(name) for name in PRESETS]
    for name, settings in zip(PRESETS, chosen):
        assert set(PRESETS[name]) <= set(PRESET_PARAMETERS)
        assert matching_preset(settings) == name
        assert describe_preset(name).startswith(settings.method.upper())
    assert len({tuple(getattr(s, k) for k in PRESET_PARAMETERS) for s in chosen}) == 3
    with pytest.raises(LPVError, match="There is no preset 'best'; choose one of fast, balanced, accurate."):
        preset_settings("best")


def test_preset_flag_starts_from_the_preset_and_given_flags_win():
    parser = build_parser()
    settings = settings_from(parser.parse_args(["demo", "--preset", "fast"]), 64, 48)
    assert settings == preset_settings("fast", width=64, height=48)
    settings = settings_from(parser.parse_args(["demo", "--preset", "accurate", "--lpv-resolution", "8"]), 64, 48)
    assert settings.lpv_resolution == 8 and settings.rsm_resolution == preset_settings("accurate").rsm_resolution
    assert matching_preset(settings) is None
    assert settings_from(parser.parse_args(["demo"]), 64, 48) == Settings(width=64, height=48)


def test_the_preset_operator_sets_the_scene_properties():
    bpy = pytest.importorskip("bpy")
    import lpv_preview
    from lpv_preview.addon.properties import settings_from_properties
    lpv_preview.register()
    scene = bpy.context.scene
    try:
        scene.lpv_preview.indirect_intensity = 2.5  # not part of a preset: kept
        for name in PRESETS:
            assert bpy.ops.lpv_preview.apply_preset(preset=name) == {"FINISHED"}
            settings = settings_from_properties(scene.lpv_preview)
            assert matching_preset(settings) == name
            assert settings.indirect_intensity == 2.5
    finally:
        scene.lpv_preview.indirect_intensity = 1.0
        for key in PRESET_PARAMETERS:
            setattr(scene.lpv_preview, key, Settings.__dataclass_fields__[key].default)
        lpv_preview.unregister()


def test_a_sweep_may_vary_the_preset(tmp_path):
    path = tmp_path / "sweeps.toml"
    path.write_text('[p]\nscenes = ["cornell"]\npreset = ["fast", "accurate"]\nwidth = 32\n'
                    '[both]\nscenes = ["cornell"]\npreset = "fast"\nmethods = ["cm"]\n'
                    '[bad]\nscenes = ["cornell"]\npreset = "quickest"\n')
    points = sweep_points(load_sweep("p", path))
    assert [(p["preset"], p["method"]) for p in points] == [(n, preset_settings(n).method) for n in ("fast", "accurate")]
    with pytest.raises(LPVError, match="needs either 'methods' or 'preset'"):
        load_sweep("both", path)
    with pytest.raises(LPVError, match="has preset 'quickest'"):
        load_sweep("bad", path)


def test_the_committed_fronts_report_still_chooses_the_presets():
    """gpu/settings.py PRESETS are what choose_presets picks from docs/bench/sweep_fronts.json."""
    report = json.loads((Path(__file__).parents[2] / "docs" / "bench" / "sweep_fronts.json").read_text())
    chosen = choose_presets(report)
    assert list(chosen) == list(PRESETS)
    for name, values in PRESETS.items():
        assert chosen[name]["settings"] == values, name
    # from fast to accurate, each takes longer and comes closer to Cycles
    times = [chosen[name]["frame_ms"] for name in PRESETS]
    errors = [chosen[name]["relative_mse_vs_cycles"] for name in PRESETS]
    assert times == sorted(times) and errors == sorted(errors, reverse=True)
