"""How many Cycles samples, and seconds, reach the error of our preview per indirect method
and of Cycles at 1 and 4 samples denoised.

    .venv/bin/python scripts/time_to_equal_error.py [cornell atrium city] [--size 128x128]
        [--reference 4096] [--ladder 1,2,4,...,256] [--kind full_gi] [--method wdpm]
        [--converge-sets 1] [--bounces 1]

For each demo scene: a high-sample Cycles reference of the current camera and frame, Cycles
at each sample count of the ladder (another seed), our preview at default settings with
each indirect method (averaging --converge-sets VPL sets, with --bounces bounces), and Cycles at 1 and 4 samples with OpenImageDenoise (addon/peers.py);
the MSE of each against the reference, and where Cycles' fitted MSE line meets it
(bench/equal_error.py). Ours is measured on its indirect and combined images, denoised
Cycles on the Combined pass (the denoiser's). Prints a Markdown row per scene, candidate
and image.
"""
import argparse

from lpv_preview.addon.comparison import full_frame, method_label
from lpv_preview.addon.cycles_reference import ReferenceCache, cycles_reference
from lpv_preview.addon.peers import DENOISED_SAMPLES, cycles_denoised
from lpv_preview.addon.render_scene import scene_and_signature_to_render
from lpv_preview.bench.equal_error import time_to_equal_error
from lpv_preview.demo import build
from lpv_preview.gpu.passes import COMPARED_PASS_NAMES
from lpv_preview.gpu.settings import INDIRECT_METHODS, Settings


def equal_error_of(scene, settings, reference_samples, ladder, kind, cache, indirect_methods=INDIRECT_METHODS,
                   denoised_samples=DENOISED_SAMPLES):
    """Cycles' reference and rungs of `scene`'s camera and frame, our preview with
    `settings` per indirect method, denoised Cycles at each of `denoised_samples`, and
    where their errors meet."""
    resolution = (settings.width, settings.height)
    lpv_scene, signature = scene_and_signature_to_render(scene, resolution)
    reference = cycles_reference(scene, kind, reference_samples, 0, resolution, cache, signature)
    rungs = [cycles_reference(scene, kind, samples, 1, resolution, cache, signature) for samples in ladder]
    candidates = []
    for indirect in indirect_methods:
        frame = full_frame(settings.with_changes(indirect_method=indirect), lpv_scene)
        label = method_label(settings.method, indirect, settings.converge_sets) + (
            f", {settings.bounces} bounces" if settings.bounces > 1 else "")
        candidates += [(label, image, frame.stats["converge_ms"], frame.passes[image]) for image in COMPARED_PASS_NAMES]
    for samples in denoised_samples:
        peer = cycles_denoised(scene, samples, resolution, signature, cache, kind)
        candidates.append((peer.name, "combined_pass", peer.seconds * 1000, peer.images["combined"]))
    return time_to_equal_error(candidates, reference, ladder, rungs)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", default=["cornell", "atrium", "city"])
    parser.add_argument("--size", default="128x128")
    parser.add_argument("--reference", type=int, default=4096)
    parser.add_argument("--ladder", default="1,2,4,8,16,32,64,128,256")
    parser.add_argument("--kind", default="full_gi")
    parser.add_argument("--method", default="wdpm")
    parser.add_argument("--converge-sets", type=int, default=1)
    parser.add_argument("--bounces", type=int, default=1)
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    ladder = [int(v) for v in args.ladder.split(",")]
    settings = Settings(method=args.method, width=width, height=height, converge_sets=args.converge_sets,
                        bounces=args.bounces)
    cache = ReferenceCache()
    print(f"| scene | candidate | image | ms | MSE | Cycles MSE at {ladder[0]} / {ladder[-1]} samples | MSE slope | "
          f"equal-error samples | Cycles s at {ladder[0]} / {ladder[-1]} | equal-error Cycles s | speed-up |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in args.scenes:
        scene = build(name)
        for result in equal_error_of(scene, settings, args.reference, ladder, args.kind, cache):
            first, last = result.ladder[0], result.ladder[-1]
            if result.samples is None:
                samples, seconds, speedup = f"< {ladder[0]}", f"< {first[1]:.2f}", "—"
            else:
                mark = " (extrapolated)" if result.extrapolated else ""
                samples, seconds = f"{result.samples:.1f}{mark}", f"{result.seconds:.2f}"
                speedup = f"{result.seconds * 1000 / result.milliseconds:.2f}x"
            image = "Combined pass" if result.image == "combined_pass" else result.image
            print(f"| {name} | {result.label} | {image} | {result.milliseconds:.0f} | {result.mse:.3g} | "
                  f"{first[2]:.3g} / {last[2]:.3g} | {result.slope:.2f} | {samples} | {first[1]:.2f} / "
                  f"{last[1]:.2f} | {seconds} | {speedup} |", flush=True)


if __name__ == "__main__":
    main()
