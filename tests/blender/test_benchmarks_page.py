"""docs/benchmarks.md is generated from the JSON reports: the page names every report's
machine and command, labels GPU and llvmpipe runs, links the plots, summarises the
presets; the committed page is what the committed reports make."""
import json
import shutil
from pathlib import Path

import pytest

from lpv_preview.bench.page import benchmarks_page, machine_label

DOCS = Path(__file__).parents[2] / "docs"


def fake_point(scene, preset, ms, cycles_psnr):
    errors = {"psnr": cycles_psnr, "relative_mse": 10 ** (-cycles_psnr / 10), "flip": 0.5}
    settings = {"method": "wdpm", "rsm_resolution": 256, "vpls_per_light": 2048, "lpv_resolution": 16,
                "propagation_iterations": 4, "width": 64, "height": 36}
    return {"scene": scene, "method": "wdpm", "preset": preset, "settings": settings, "triangles": 900,
            "timings_ms": {"total_ms": ms, "total_ms_spread": [ms, ms]}, "gpu_bytes": 2**20, "vpl_count": 2048,
            "error_size": [64, 36], "errors_vs_cm": errors, "errors_vs_cycles": errors, "cycles_samples": 16}


def fake_report(renderer):
    return {"schema": 1, "sweep": "presets", "description": "d", "cycles_samples": 16, "scaling": [],
            "choose_presets": False, "machine": {"renderer": renderer, "version": "4.5 (Core Profile) Mesa"},
            "date": "2026-11-23", "repeats": 1, "seconds": 1.0, "command": "python -m lpv_preview bench --sweep presets",
            "points": [fake_point("box.npz", "fast", 3.0, 12.5), fake_point("box.npz", "balanced", 5.0, 13.25)]}


def test_the_page_labels_machines_and_lists_every_report(tmp_path):
    (tmp_path / "bench" / "llvmpipe").mkdir(parents=True)
    (tmp_path / "bench" / "sweep_presets.json").write_text(json.dumps(fake_report("NVIDIA H100 80GB HBM3/PCIe/SSE2")))
    (tmp_path / "bench" / "llvmpipe" / "sweep_presets.json").write_text(
        json.dumps(fake_report("llvmpipe (LLVM 15.0.6, 256 bits)")))
    (tmp_path / "bench" / "pareto_presets_box.png").write_bytes(b"png")
    page = benchmarks_page(tmp_path / "benchmarks.md")
    assert "## Sweep `presets` on the GPU" in page and "## Sweep `presets` on the CPU (llvmpipe)" in page
    assert "report [bench/sweep_presets.json](bench/sweep_presets.json)" in page
    assert "![pareto_presets_box](bench/pareto_presets_box.png)" in page
    assert page.count("    python -m lpv_preview bench --sweep presets") == 2
    assert "| box | balanced | 5.00 | 13.25 |" in page
    assert machine_label("llvmpipe (LLVM 15.0.6, 256 bits)") == "CPU (llvmpipe)"


def test_the_committed_page_is_what_the_committed_reports_make(tmp_path):
    shutil.copytree(DOCS / "bench", tmp_path / "bench")
    assert benchmarks_page(tmp_path / "benchmarks.md") == (DOCS / "benchmarks.md").read_text()


def test_the_page_command_says_when_there_are_no_reports(tmp_path, capsys):
    pytest.importorskip("bpy")
    from lpv_preview.__main__ import main
    assert main(["bench", "--page", str(tmp_path / "missing" / "benchmarks.md")]) == 2
    assert "There are no sweep reports under" in capsys.readouterr().err
