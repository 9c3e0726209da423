"""Timing a pipeline: whole frames with every stage redone, and one stage's throughput.

Both warm the GPU up first: its clocks drop while the CPU measures quality between
points (the H100 idles at 345 MHz against 1980 under load).
"""
import statistics
import time

from ..gpu.pipeline import STAGES

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
