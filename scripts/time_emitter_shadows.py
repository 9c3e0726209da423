"""The emitters' shadows' per-pixel pass alone (gpu/emitter_shadows.py EmitterShadows.apply:
one light grid lookup giving the shadowed and unshadowed luminance), repeated on one frame
of the particle room at 1920×1080, without Blender:

    python scripts/time_emitter_shadows.py [--emitters 1048576] [--runs 50]

Prints the median, least and most milliseconds of the pass by the wall clock, the GPU
finished before and after each, after ten runs that warm the GPU up.
"""
import argparse
import statistics
import time

from lpv_preview.bench.synthetic import particle_room
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import preset_settings
from lpv_preview.gpu.shade import bind_gbuffer, gbuffer_uniforms

WARM_UP_RUNS = 10


def main():
    parser = argparse.ArgumentParser(description="the emitters' shadows' per-pixel pass on the GPU")
    parser.add_argument("--emitters", type=int, default=1 << 20)
    parser.add_argument("--runs", type=int, default=50)
    args = parser.parse_args()
    scene = particle_room(args.emitters, seed=1)
    pipeline = Pipeline(preset_settings(None, width=1920, height=1080))
    try:
        pipeline.render(scene)
        shadows, grid, targets = pipeline._emitter_shadows.value, pipeline._emitter_grid.value, pipeline.targets
        image, uniforms, gl = grid._image(targets.size), gbuffer_uniforms(scene.camera), pipeline.glc.gl
        times = []
        for _ in range(WARM_UP_RUNS + args.runs):
            bind_gbuffer(targets)
            gl.finish()
            start = time.perf_counter()
            shadows.apply(targets, uniforms, image)
            gl.finish()
            times.append((time.perf_counter() - start) * 1e3)
        times = times[WARM_UP_RUNS:]
        print(f"{pipeline.glc.renderer}: the shadows' pass {statistics.median(times):.3f} ms "
              f"({min(times):.3f}-{max(times):.3f}) over {args.runs} runs, {args.emitters} emitters")
    finally:
        pipeline.release()


if __name__ == "__main__":
    main()
