"""How many Cycles samples, and seconds, reach the error of our default preview.

    .venv/bin/python scripts/time_to_equal_error.py [cornell atrium city] [--size 128x128]
        [--reference 4096] [--ladder 1,2,4,...,256] [--kind full_gi] [--method wdpm]

For each demo scene: a high-sample Cycles reference of the current camera and frame, Cycles
at each sample count of the ladder (another seed), our preview at default settings; the
MSE of each against the reference, and where Cycles' fitted MSE line meets ours
(bench/equal_error.py). Prints a Markdown row per scene and image.
"""
import argparse

from lpv_preview.addon.comparison import full_frame
from lpv_preview.addon.cycles_reference import ReferenceCache, cycles_reference
from lpv_preview.addon.render_scene import scene_to_render
from lpv_preview.bench.equal_error import time_to_equal_error
from lpv_preview.demo import build
from lpv_preview.gpu.settings import Settings


def equal_error_of(scene, settings, reference_samples, ladder, kind, cache):
    """Cycles' reference and rungs of `scene`'s camera and frame, our preview with
    `settings`, and where their errors meet."""
    resolution = (settings.width, settings.height)
    lpv_scene = scene_to_render(scene, resolution)
    reference = cycles_reference(scene, kind, reference_samples, 0, resolution, cache, lpv_scene)
    rungs = [cycles_reference(scene, kind, samples, 1, resolution, cache, lpv_scene) for samples in ladder]
    return time_to_equal_error(full_frame(settings, lpv_scene), reference, ladder, rungs)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", default=["cornell", "atrium", "city"])
    parser.add_argument("--size", default="128x128")
    parser.add_argument("--reference", type=int, default=4096)
    parser.add_argument("--ladder", default="1,2,4,8,16,32,64,128,256")
    parser.add_argument("--kind", default="full_gi")
    parser.add_argument("--method", default="wdpm")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    ladder = [int(v) for v in args.ladder.split(",")]
    settings = Settings(method=args.method, width=width, height=height)
    cache = ReferenceCache()
    print(f"| scene | image | ours ms | our MSE | Cycles MSE at {ladder[0]} / {ladder[-1]} samples | MSE slope | "
          f"equal-error samples | Cycles s at {ladder[0]} / {ladder[-1]} | equal-error Cycles s | speed-up |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name in args.scenes:
        scene = build(name)
        for result in equal_error_of(scene, settings, args.reference, ladder, args.kind, cache):
            first, last = result.ladder[0], result.ladder[-1]
            if result.samples is None:
                samples, seconds, speedup = f"< {ladder[0]}", f"< {first[1]:.2f}", "—"
            else:
                mark = " (extrapolated)" if result.extrapolated else ""
                samples, seconds = f"{result.samples:.1f}{mark}", f"{result.seconds:.2f}"
                speedup = f"{result.seconds * 1000 / result.our_ms:.2f}x"
            print(f"| {name} | {result.image} | {result.our_ms:.0f} | {result.our_mse:.3g} | {first[2]:.3g} / "
                  f"{last[2]:.3g} | {result.slope:.2f} | {samples} | {first[1]:.2f} / {last[1]:.2f} | {seconds} | "
                  f"{speedup} |", flush=True)


if __name__ == "__main__":
    main()
