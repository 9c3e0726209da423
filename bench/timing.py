"""Timing a pipeline: whole frames with every stage redone, and one stage's throughput.

Both warm the GPU up first: its clocks drop while the CPU measures quality between
points (the H100 idles at 345 MHz against 1980 under load).
"""
import argparse
import json
import statistics
import time

from ..gpu.pipeline import STAGES, Pipeline
from ..gpu.scene_file import load_scene

WARM_UP_FRAMES = 2
THROUGHPUT_WARM_UP_SECONDS = 0.5  # of work before timing: brings the GPU's clocks up


def timed_frames(pipeline, scene, repeats, passes=None):
    """Median stage and frame milliseconds with every stage redone, after full warm-up
    frames for at least THROUGHPUT_WARM_UP_SECONDS: the GPU's clocks drop while the CPU
    measures quality between points (the H100 idles at 345 MHz against 1980 under load).
    A frame averages the VPL sets its settings ask for (Pipeline.render_converged): its
    `total_ms` is all of them, its stages the last one's. `passes` are read back each
    frame (None: every pass; () times the GPU work alone)."""
    kwargs = {} if passes is None else {"passes": passes}
    warm_up_until = time.perf_counter() + THROUGHPUT_WARM_UP_SECONDS
    frames = 0
    while frames < WARM_UP_FRAMES or time.perf_counter() < warm_up_until:
        pipeline.invalidate()
        pipeline.render_converged(scene, **kwargs)
        frames += 1
    samples = []
    for _ in range(repeats):
        pipeline.invalidate()
        stats = pipeline.render_converged(scene, **kwargs).stats
        samples.append({**stats, "total_ms": stats["converge_ms"]})
    keys = (*(key for key in STAGES if any(key in s for s in samples)), "total_ms")  # the stages that ran
    keys += tuple("gpu_" + key for key in keys[:-1] if any("gpu_" + key in s for s in samples))
    result = {key: statistics.median(s.get(key, 0.0) for s in samples) for key in keys}
    result["total_ms_spread"] = [min(s["total_ms"] for s in samples), max(s["total_ms"] for s in samples)]
    return result, samples[-1]


THROUGHPUT_RUNS = 20


def throughput_ms(glc, work, runs=THROUGHPUT_RUNS):
    """Milliseconds per call of `work`, run `runs` times back to back, by the wall clock
    with the GPU finished before and after. A single call timed alone (even by GPU timer
    queries) also counts the GPU idling while Python submits. Before timing, `work` runs
    for THROUGHPUT_WARM_UP_SECONDS: after the CPU-side quality measurements the GPU's
    clocks are down, and one call does not bring them back (the same DPM render timed
    4.1 and 8.3 ms in two bench runs with a single warm-up call)."""
    warm_up_until = time.perf_counter() + THROUGHPUT_WARM_UP_SECONDS
    while True:
        work()
        glc.gl.finish()
        if time.perf_counter() >= warm_up_until:
            break
    start = time.perf_counter()
    for _ in range(runs):
        work()
    glc.gl.finish()
    return (time.perf_counter() - start) * 1000.0 / runs


def frame_summary(times, stages):
    """Of timed_frames' medians: the frame's milliseconds with its least and most, and the
    `stages`' medians (0 for one that did not run), rounded for a report."""
    low, high = times["total_ms_spread"]
    return {"frame_ms": round(times["total_ms"], 2), "least_ms": round(low, 2), "most_ms": round(high, 2),
            **{stage: round(times.get(stage, 0.0), 2) for stage in stages}}


def time_cases(folder, names, frames, cases, stages):
    """The JSON report of exported scenes' variants: for each FOLDER/NAME.npz of `names`,
    `cases(scene)` gives (case, scene, settings) triples, each timed over `frames` frames
    (timed_frames) and summed up with `stages` (frame_summary; `bounces` from the last
    frame's statistics)."""
    report, renderer = {}, None
    for name in names:
        for case, scene, settings in cases(load_scene(f"{folder}/{name}.npz")):
            pipeline = Pipeline(settings)
            try:
                times, last = timed_frames(pipeline, scene, frames, passes=())
                renderer = pipeline.glc.renderer
            finally:
                pipeline.release()
            report[f"{name}, {case}"] = {"bounces": last["bounces"], **frame_summary(times, stages)}
    return {"renderer": renderer, "frames": frames, "runs": report}


def time_cases_command(description, cases, stages):
    """A script's command line: `DIR NAME [NAME ...] [--frames 15]`, the time_cases report
    printed as JSON."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("folder", help="the folder of NAME.npz files (python -m lpv_preview export NAME)")
    parser.add_argument("names", nargs="+")
    parser.add_argument("--frames", type=int, default=15, help="timed frames per median")
    args = parser.parse_args()
    print(json.dumps(time_cases(args.folder, args.names, args.frames, cases, stages), indent=1))
