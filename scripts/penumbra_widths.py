"""Prints the penumbra widths of soft shadows against Cycles', and what soft shadows cost
a frame (issue 31; docs/accuracy.md, "Soft shadows").

    python scripts/penumbra_widths.py [--samples 256] [--sets 8]

Each light stands over the plate's edge of demo/shadow_edge.py (128 x 8 pixels over 2 m);
a width is the 10-90 % rise of the shadowed image over the unshadowed one, ours (the
direct pass, `--sets` VPL sets averaged) and Cycles' Diffuse Direct. The cost is the
direct stage's wall clock after ctx.finish() (llvmpipe here), the median of five frames
of a 256 x 256 view of the same scene, soft against the same light of no size.
"""
import argparse
import math
import time

import bpy
import numpy as np

from lpv_preview.addon.cycles_reference import render_cycles_passes
from lpv_preview.addon.extract import extract_scene
from lpv_preview.demo import shadow_edge
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import Settings

parser = argparse.ArgumentParser(description="penumbra widths against Cycles, and the cost of soft shadows")
parser.add_argument("--samples", type=int, default=256)
parser.add_argument("--sets", type=int, default=8)
args = parser.parse_args()
WIDTH, HEIGHT = 128, 8
LIGHTS = (("SUN", math.radians(15.0), "sun, 15 degrees"), ("SUN", math.radians(5.0), "sun, 5 degrees"),
          ("AREA", 0.5, "area square, 0.5 m"), ("AREA", 1.0, "area square, 1.0 m"),
          ("POINT", 0.25, "point, radius 0.25 m"), ("SPOT", 0.1, "spot, radius 0.1 m"))


def widths(kind, size):
    shadow_edge.build(kind, size, WIDTH, HEIGHT)
    pipeline = Pipeline(Settings(width=WIDTH, height=HEIGHT, converge_sets=args.sets))
    ours, cycles = [], []
    for shown in (True, False):
        shadow_edge.show_plate(shown)
        ours.append(pipeline.render_converged(extract_scene(bpy.context.evaluated_depsgraph_get()),
                                              passes=("direct",)).passes["direct"])
        cycles.append(render_cycles_passes(bpy.context.scene, passes=("DiffDir",), samples=args.samples,
                                           pixel_filter_width=0.01, max_bounces=0)["DiffDir"])
    pipeline.release()
    return [shadow_edge.penumbra_width(shadow_edge.edge_profile(*images)) for images in (ours, cycles)]


def direct_ms(kind, size, taps=32):
    """The median wall clock of the direct stage (ms) over five frames, after ctx.finish()."""
    shadow_edge.build(kind, size, 256, 256)
    scene = extract_scene(bpy.context.evaluated_depsgraph_get())
    pipeline = Pipeline(Settings(width=256, height=256, shadow_taps=taps))
    pipeline.render(scene, passes=())
    times = []
    for vpl_set in range(5):
        pipeline.glc.gl.finish()
        frame = pipeline.render(scene, passes=(), vpl_set=vpl_set)
        times.append(frame.stats["direct_ms"])
    pipeline.release()
    return float(np.median(times))


print(f"Penumbra 10-90 % widths, ours ({args.sets} VPL sets) against Cycles ({args.samples} samples):")
print(f"{'light':24} {'ours cm':>8} {'Cycles cm':>10} {'difference':>11}")
for kind, size, label in LIGHTS:
    ours, cycles = widths(kind, size)
    print(f"{label:24} {ours * 100:8.2f} {cycles * 100:10.2f} {ours / cycles - 1:+11.1%}")
print("\nDirect stage per frame, 256 x 256 (llvmpipe, wall clock after ctx.finish(), median of 5):")
print(f"{'light':24} {'no size ms':>10} {'16 taps ms':>11} {'32 taps ms':>11} {'64 taps ms':>11}")
for kind, size, label in LIGHTS[::2]:
    hard = direct_ms(kind, 0.0)
    soft = [direct_ms(kind, size, taps) for taps in (16, 32, 64)]
    print(f"{label:24} {hard:10.2f} " + " ".join(f"{ms:11.2f}" for ms in soft))
