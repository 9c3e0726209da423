"""The host's read of a scene's emissive particles, as a viewport redraw reads them in
each frame they move, with real bpy: the demo particle room (demo/particles.py) with
COUNT particles, its evaluated depsgraph read by addon/extract.py `extract_parts`, the
median of five reads.

    python scripts/time_particle_extraction.py [COUNT ...]

Prints per count the milliseconds of the whole read, of the point emitters' bulk read
(addon/point_emitters.py) within it, which is all a viewport reads again when only their
instancer moved (addon/sync.py EMITTERS), and of a bare walk over the depsgraph's
instances, and the whole read's microseconds a particle. The GPU's emitter frame
(scripts/time_viewport_work.py) starts from the Scene this read makes.
"""
import statistics
import sys
import time

import bpy
import numpy as np

from lpv_preview.addon.extract import extract_parts, extract_point_emitters
from lpv_preview.demo import particles

READS = 5


def median_ms(work):
    times = []
    for _ in range(READS):
        start = time.perf_counter()
        work()
        times.append((time.perf_counter() - start) * 1000.0)
    return statistics.median(times)


for count in [int(arg) for arg in sys.argv[1:]] or [10_000, 100_000]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    particles.build(particles=count)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    extract_parts(depsgraph)  # materials and meshes read once, as a viewport has
    whole = median_ms(lambda: extract_parts(depsgraph))
    bulk = median_ms(lambda: extract_point_emitters(depsgraph).array(np.zeros(3)))
    walk = median_ms(lambda: sum(1 for _ in depsgraph.object_instances))
    print(f"{count} particles: read {whole:.1f} ms ({whole * 1000 / count:.2f} µs a particle), "
          f"the point emitters' bulk read (a move of their instancer alone) {bulk:.1f} ms, the bare walk over the "
          f"instances {walk:.1f} ms", flush=True)
