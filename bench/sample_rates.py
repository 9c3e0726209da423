"""Cycles sample workers (issue 18): the fixed cost of one request and the cost of a
sample, and samples a second with 1, 2 and 4 workers. bpy lives with the caller, who
hands in a renderer, the request type (corrections/sample_request.py SampleRequest) and a way to start
workers (`python -m lpv_preview bench --sample-workers`)."""
import json
import time
from pathlib import Path

import numpy as np

from .plots import pyplot, save

REGIONS = (1, 8, 32)  # square regions' sides, pixels
SAMPLES = (1, 4, 16, 64)
WORKER_COUNTS = (1, 2, 4)
SCALING_REQUESTS = 12
"""Requests each worker renders in the scaling measurement."""


def request_costs(render, request_of, resolution, repeats=3, log=print):
    """Seconds of requests of every region in REGIONS and sample count in SAMPLES (the
    median of `repeats`, after one unmeasured request), and the least-squares fit
    seconds = fixed + per_sample × pixels × samples."""
    render(request_of((0, 0, 1, 1), resolution, 1))
    rows = []
    for side in REGIONS:
        for samples in SAMPLES:
            request = request_of((0, 0, side, side), resolution, samples)
            times = []
            for _ in range(repeats):
                start = time.perf_counter()
                render(request)
                times.append(time.perf_counter() - start)
            rows.append({"pixels": side * side, "samples": samples, "seconds": float(np.median(times))})
            log(json.dumps(rows[-1]))
    work = np.array([row["pixels"] * row["samples"] for row in rows], dtype=np.float64)
    seconds = np.array([row["seconds"] for row in rows])
    per_sample, fixed = np.polyfit(work, seconds, 1)
    return {"rows": rows, "fixed_ms": float(fixed * 1e3), "samples_per_second": float(1.0 / per_sample)}


def worker_scaling(start_workers, request_of, resolution, region=64, samples=16,
                   requests_per_worker=SCALING_REQUESTS, log=print):
    """Samples a second of `requests_per_worker` requests a worker of `region`² pixels at
    `samples` each, for each count in WORKER_COUNTS; `start_workers(n)` gives a context
    manager with `open_everywhere()`, `submit(request)` and `client.gather(futures)`
    (corrections/sample_workers.py). Every worker opens the .blend and renders one request
    first (Cycles warm)."""
    rows = []
    width, height = resolution
    for count in WORKER_COUNTS:
        with start_workers(count) as workers:
            workers.open_everywhere()
            warm = [workers.submit(request_of((0, 0, region, region), resolution, 1, seed=-1 - i))
                    for i in range(count)]
            workers.client.gather(warm)
            requests = [request_of(((i * region) % (width - region + 1), 0,
                                       (i * region) % (width - region + 1) + region, region),
                                      resolution, samples, seed=i) for i in range(count * requests_per_worker)]
            start = time.perf_counter()
            workers.client.gather([workers.submit(request) for request in requests])
            seconds = time.perf_counter() - start
        rows.append({"workers": count, "seconds": seconds, "region": region, "samples": samples,
                     "samples_per_second": len(requests) * region * region * samples / seconds})
        log(json.dumps(rows[-1]))
    for row in rows:
        row["speed_up"] = row["samples_per_second"] / rows[0]["samples_per_second"]
    return rows


def write_sample_report(report, out):
    """sample_workers.json, sample_workers.md and the scaling plot sample_workers.png in the folder `out`."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "sample_workers.json").write_text(json.dumps(report, indent=1))
    plot = _scaling_plot(report["scaling"], out / "sample_workers.png")
    costs = report["costs"]
    lines = [f"### Cycles sample requests ({report['machine']})", "",
             f"One renderer, the {report['scene']} at {report['resolution'][0]}×{report['resolution'][1]}: a request "
             f"costs {costs['fixed_ms']:.1f} ms beyond its samples, and Cycles traces "
             f"{costs['samples_per_second']:,.0f} samples a second (least squares over the table).", "",
             "| pixels | samples | ms |", "|---:|---:|---:|"]
    lines += [f"| {row['pixels']} | {row['samples']} | {row['seconds'] * 1e3:.1f} |" for row in costs["rows"]]
    first = report["scaling"][0]
    lines += ["", "### Workers on Dask (local processes)", "",
              f"Requests of {first['region']}×{first['region']} pixels at {first['samples']} samples each, "
              f"{SCALING_REQUESTS} a worker.",
              "", "| workers | samples / s | speed-up |", "|---:|---:|---:|"]
    lines += [f"| {row['workers']} | {row['samples_per_second']:,.0f} | {row['speed_up']:.2f}× |"
              for row in report["scaling"]]
    if plot is not None:
        lines += ["", f"![samples a second against workers]({plot.name})"]
    lines += ["", f"Command: `{report['command']}`"]
    (out / "sample_workers.md").write_text("\n".join(lines) + "\n")
    return {"out": str(out)}


def _scaling_plot(rows, path):
    """Samples a second against the number of workers, beside perfect scaling."""
    plt = pyplot()
    if plt is None:
        return None
    figure, axes = plt.subplots(figsize=(5.2, 3.8), dpi=100)
    workers = [row["workers"] for row in rows]
    axes.plot(workers, [row["samples_per_second"] for row in rows], marker="o", label="measured")
    axes.plot(workers, [rows[0]["samples_per_second"] * count for count in workers], linestyle=":", color="grey",
              label="perfect scaling")
    axes.set_xticks(workers)
    return save(plt, figure, axes, ("local Dask workers (one Cycles thread each)", "Cycles samples a second"),
                "Cycles sample workers on one machine", path)
