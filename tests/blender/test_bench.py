"""The bench command runs every method on a demo scene and writes Table 1."""
import json
import math

import pytest

pytest.importorskip("bpy")

from lpv_preview.__main__ import main  # noqa: E402


def test_tiny_bench_writes_table_one(tmp_path):
    out = tmp_path / "bench"
    argv = ["bench", "--scenes", "cornell", "--methods", "cm,dpm,wdpm,tdpm,twdpm", "--frames", "2", "--repeats", "1",
            "--width", "64", "--height", "64", "--rsm-resolution", "64", "--vpls-per-light", "256",
            "--lpv-resolution", "8", "--bounces", "1", "--out", str(out)]  # Table 1: one bounce
    assert main(argv) == 0
    report = json.loads((out / "table1.json").read_text())
    (result,) = report["results"]
    assert result["scene"] == "cornell" and result["lights"] == ["POINT"]
    assert sorted(result["methods"]) == ["cm", "dpm", "tdpm", "twdpm", "wdpm"]
    for method in ("dpm", "wdpm", "tdpm", "twdpm"):
        row = result["methods"][method]
        for key in ("lpv_psnr_mean", "lpv_psnr_min", "dpm_flux_psnr", "dpm_position_psnr"):
            assert math.isfinite(row[key]) and row[key] > 10, (method, key, row[key])
        assert row["timing"]["rsm_ms"] > 0 and row["timing"]["rsm_throughput_ms"] > 0
        assert (row["timing"]["warp_throughput_ms"] > 0) == (method in ("wdpm", "twdpm"))
    for method in ("wdpm", "twdpm"):
        shares = result["methods"][method]["warp_status_after"]
        assert sorted(map(int, shares)) == [1, 4, 8, 16]
        for share in shares.values():
            assert sum(share.values()) == pytest.approx(1.0)
    reference = result["sampling_reference"]
    assert len(reference["lpv_psnr_frames"]) == 2 and 10 < reference["lpv_psnr_min"] <= reference["lpv_psnr_mean"]
    assert math.isfinite(reference["lpv_psnr_mean"])
    table = (out / "table1.md").read_text()
    assert "| cornell | 900 | equal-resolution | WDPM |" in table and "python -m lpv_preview bench" in table
    assert "| cornell | 900 | equal-resolution | CM turned 45° (sampling reference) |" in table
