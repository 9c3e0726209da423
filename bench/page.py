"""docs/benchmarks.md, made from the JSON reports under docs/bench alone: every figure on
the page comes from a report, with the machine, its driver and the command that measured
it. GPU reports lie in docs/bench, llvmpipe ones in docs/bench/llvmpipe; the page keeps
both, labelled. `python -m lpv_preview bench --page docs/benchmarks.md` writes it again."""
import os
from pathlib import Path

from ..gpu.errors import LPVError
from .emitters import emitter_report_markdown
from .sweep_report import (choose_presets, error_cell, machine_line, markdown_report, presets_table, read_report,
                           scene_label, write_sweep_outputs)
from .table1 import markdown_table

SWEEP_ORDER = ("presets", "presets_cpu", "fronts", "methods", "texels", "triangles", "lights", "quick")
"""The order of the sweeps on the page: what a user chooses by first, then how it scales."""


def machine_label(renderer):
    """'GPU' or 'CPU (llvmpipe)' for a GL renderer string."""
    return "CPU (llvmpipe)" if "llvmpipe" in renderer.lower() else "GPU"


def _demoted(markdown):
    """A report's headings one level down, to sit under the page's sections."""
    return "\n".join("#" + line if line.startswith("###") else line for line in markdown.splitlines())


def _sweep_section(path, report, page_dir):
    name = report["sweep"]
    label = machine_label(report["machine"]["renderer"])
    relative = os.path.relpath(path, page_dir)
    folder = Path(path).parent
    plots = sorted(folder.glob(f"pareto_{name}_*.png")) + sorted(folder.glob(f"scaling_{name}_*.png"))
    lines = [f"## Sweep `{name}` on the {label}", "",
             f"From the report [{relative}]({relative}); the command below makes it again.", ""]
    lines += [f"![{plot.stem}]({os.path.relpath(plot, page_dir)})" for plot in plots]
    if plots:
        lines.append("")
    lines.append(_demoted(markdown_report(report, report.get("command"))))
    return lines


def _table1_section(path, report, page_dir):
    relative = os.path.relpath(path, page_dir)
    label = machine_label(report["machine"])
    return [f"## `bench` (Table 1 of the thesis) `{Path(path).stem}` on the {label}", "",
            f"Report [{relative}]({relative}).", "", f"    {report['command']}", "",
            markdown_table(report["results"], report["machine"])]


def _presets_summary(reports):
    """The presets chosen from the fronts sweep, and each preset's figures per scene."""
    lines = []
    for path, report in reports:
        if report.get("choose_presets"):
            lines += [f"Chosen by `choose_presets` (bench/sweep_report.py) from the `{report['sweep']}` sweep on "
                      f"{machine_line(report['machine'])}; the values live in "
                      f"gpu/settings.py `PRESETS`. Mean over its scenes:", "", *presets_table(choose_presets(report)),
                      ""]
    for path, report in reports:
        if not any("preset" in point for point in report["points"]):
            continue
        first = report["points"][0]["settings"]
        lines += [f"Each preset on each scene on the {machine_label(report['machine']['renderer'])}, from the "
                  f"`{report['sweep']}` sweep ({machine_line(report['machine'])}), frames of "
                  f"{first['width']}×{first['height']}, errors at each scene's reference size:", "",
                  "| scene | preset | frame ms | indirect PSNR vs Cycles dB | relMSE vs Cycles | FLIP vs Cycles | "
                  "PSNR vs CM-LPV dB |", "|---|---|---|---|---|---|---|"]
        for point in report["points"]:
            cycles, cube = point.get("errors_vs_cycles", {}), point["errors_vs_cm"]
            lines.append(f"| {scene_label(point['scene'])} | {point['preset']} | {point['timings_ms']['total_ms']:.2f} | "
                         f"{error_cell(cycles, 'psnr', '.2f')} | {error_cell(cycles, 'relative_mse', '.3g')} | "
                         f"{error_cell(cycles, 'flip', '.3f')} | {error_cell(cube, 'psnr', '.2f')} |")
        lines.append("")
    return lines


def _emitters_section(path, report, page_dir):
    relative = os.path.relpath(path, page_dir)
    return [f"## Many emitters (`bench --emitters`) on the {machine_label(report['counts'][0]['renderer'])}", "",
            f"Report [{relative}]({relative}).", "", emitter_report_markdown(report)]


def _cycles_sections(reports, page_dir):
    """The corrections toward Cycles and the Cycles sample workers: their reports' Markdown
    (tables too wide for the page) and plots, linked."""
    lines = []
    for path, report in reports:
        if "reference_samples" in report:
            title, pattern = "Corrections toward Cycles (`bench --corrections`)", "corrections_*.png"
            summary = "; docs/accuracy.md sums it up"
        elif "costs" in report:
            title, pattern, summary = "Cycles sample workers (`bench --sample-workers`)", "sample_workers.png", ""
        else:
            continue
        markdown = os.path.relpath(Path(path).with_suffix(".md"), page_dir)
        plots = sorted(Path(path).parent.glob(pattern))
        lines += [f"## {title} on {report['machine']}", "", f"Report [{markdown}]({markdown}){summary}.", "",
                  *[f"![{plot.stem}]({os.path.relpath(plot, page_dir)})" for plot in plots], ""]
    return lines


def read_reports(page_path):
    """(path, report) of every JSON report in the folder `bench` beside the page."""
    return [(path, read_report(path)) for path in sorted((Path(page_path).parent / "bench").rglob("*.json"))]


def benchmarks_page(page_path, reports=None):
    """The page's Markdown from `reports` (default: `read_reports(page_path)`): sweep
    reports and Table 1 reports."""
    page_dir = Path(page_path).parent
    reports = read_reports(page_path) if reports is None else reports
    sweeps = [(path, report) for path, report in reports if "sweep" in report]
    tables = [(path, report) for path, report in reports if "results" in report]
    emitters = [(path, report) for path, report in reports if "counts" in report]
    rank = lambda item: (SWEEP_ORDER.index(item[1]["sweep"]) if item[1]["sweep"] in SWEEP_ORDER else len(SWEEP_ORDER),
                         str(item[0]))
    sweeps.sort(key=rank)
    lines = ["# Benchmarks", "",
             "Generated from the JSON reports under docs/bench by `python -m lpv_preview bench --page "
             "docs/benchmarks.md`; do not edit by hand. Each section names the machine, its driver and the command "
             "that measured it. GPU figures are timings; llvmpipe figures only compare settings with each other on "
             "the CPU. Analysis, and timings measured by scripts: docs/performance.md.", "",
             "Contents: presets; " + "; ".join(f"sweep `{r['sweep']}` ({machine_label(r['machine']['renderer'])})"
                                               for _, r in sweeps) + "; Table 1" +
             ("; many emitters" if emitters else "") + "; corrections toward Cycles and their sample workers.", "",
             "## Presets", "", *_presets_summary(sweeps)]
    for path, report in sweeps:
        lines += _sweep_section(path, report, page_dir) + [""]
    for path, report in tables:
        lines += _table1_section(path, report, page_dir) + [""]
    for path, report in emitters:
        lines += _emitters_section(path, report, page_dir) + [""]
    lines += _cycles_sections(reports, page_dir)
    return "\n".join(lines).rstrip() + "\n"


def write_benchmarks_page(page):
    """Every sweep report's table and plots beside it again, then the page from them all."""
    reports = read_reports(page)
    sweeps = [(path, report) for path, report in reports if "sweep" in report]
    if not sweeps:
        raise LPVError(f"There are no sweep reports under {os.path.join(os.path.dirname(page), 'bench')}; run "
                       f"`bench --sweep` first.")
    for path, report in sweeps:
        write_sweep_outputs(report, str(path.parent), write_json=False)
    text = benchmarks_page(page, reports)
    try:
        with open(page, "w") as handle:
            handle.write(text)
    except OSError as error:
        raise LPVError(f"Cannot write the benchmarks page '{page}' ({error.strerror}); choose a writable path.")
    return {"page": page, "reports": [str(path) for path, _ in sweeps]}
