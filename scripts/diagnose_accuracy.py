"""Which stage loses the accuracy against Cycles: the stages swapped for exact ones.

    .venv/bin/python scripts/diagnose_accuracy.py [--scene cornell] [--size 128] [--samples 1024] [--method wdpm]

Renders the demo scene's Cycles one-bounce reference (cached), then prints the indirect
image's errors against it for: Cycles itself at a quarter of the samples and another
seed (the reference's noise floor); the method at default settings with each indirect
method (LPV, light grid); the grid swapped for the exact transfer from the same VPLs
(bench/exact_stages.py: no grid, no SH, no visibility); that with 65,536 VPLs (the VPL
sampling swapped too); and the same with the scene's blocks hidden, where no surface
hides one from another, so the missing visibility is swapped out as well. Last, the
LPV alone (its own grid, 16³ by default): its image for a few
propagation settings against the exact transfer from the same VPLs, with the ratio of
their means over each quarter of the picture's rows, top to bottom.
"""
import argparse

import bpy

from lpv_preview.addon.cycles_reference import ReferenceCache, cycles_reference
from lpv_preview.addon.render_scene import scene_to_render
from lpv_preview.demo import build
from lpv_preview.bench.exact_stages import gathered_indirect
from lpv_preview.gpu.metrics import image_errors
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import INDIRECT_METHODS, Settings

ALL_TEXELS = 65536
BLOCKS = {"cornell": ("Short box", "Tall box")}


def row(label, image, reference):
    errors = image_errors(image, reference.indirect)
    print(f"| {label} | {errors['psnr']:.2f} | {errors['relative_mse']:.4f} | {errors['ssim']:.3f} | "
          f"{errors['flip']:.3f} | {image.mean() / reference.indirect.mean():.3f} |", flush=True)


def method_rows(scene_label, settings, reference):
    scene = scene_to_render(bpy.context.scene, (settings.width, settings.height))
    for indirect in INDIRECT_METHODS:
        pipeline = Pipeline(settings.with_changes(indirect_method=indirect))
        try:
            row(f"{scene_label}: {settings.method.upper()}, {indirect} {settings.lpv_resolution}³, "
                f"{settings.vpls_per_light} VPLs", pipeline.render(scene).passes["indirect"], reference)
        finally:
            pipeline.release()
    for vpls in (settings.vpls_per_light, ALL_TEXELS):
        pipeline = Pipeline(settings.with_changes(vpls_per_light=vpls))
        try:
            pipeline.render(scene)
            row(f"{scene_label}: exact transfer from {vpls} VPLs (no grid, no visibility)",
                gathered_indirect(pipeline, scene.camera), reference)
        finally:
            pipeline.release()


LPV_VARIANTS = ({}, {"propagation_iterations": 16}, {"propagation_iterations": 32},
                {"propagation_iterations": 32, "occlusion": False})


def lpv_alone_rows(settings):
    """The LPV for each of LPV_VARIANTS against the exact transfer from the same VPLs."""
    scene = scene_to_render(bpy.context.scene, (settings.width, settings.height))
    print("\n| LPV settings | PSNR dB against the exact transfer | mean / exact | quarters of rows / exact |\n"
          "|---|---|---|---|")
    for changes in LPV_VARIANTS:
        pipeline = Pipeline(settings.with_changes(**changes))
        try:
            lpv = pipeline.render(scene).passes["indirect"]
            exact = gathered_indirect(pipeline, scene.camera)
        finally:
            pipeline.release()
        quarters = [lpv[q * len(lpv) // 4:(q + 1) * len(lpv) // 4].mean() /
                    exact[q * len(exact) // 4:(q + 1) * len(exact) // 4].mean() for q in range(4)]
        label = ", ".join(f"{k} {v}" for k, v in changes.items()) or "defaults"
        print(f"| {label} | {image_errors(lpv, exact)['psnr']:.2f} | {lpv.mean() / exact.mean():.3f} | "
              f"{' / '.join(f'{q:.2f}' for q in quarters)} |", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="cornell", choices=sorted(BLOCKS))
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--samples", type=int, default=1024)
    parser.add_argument("--method", default="wdpm")
    args = parser.parse_args()
    cache = ReferenceCache()
    settings = Settings(method=args.method, width=args.size, height=args.size)
    scene = build(args.scene)
    resolution = (args.size, args.size)
    reference = cycles_reference(scene, "one_bounce", args.samples, 0, resolution, cache)
    print(f"{args.scene}, {args.size}x{args.size}, Cycles one bounce {args.samples} samples "
          f"({reference.settings['render_seconds']:.1f} s), indirect image:\n")
    print("| what is approximate | PSNR dB | relMSE | SSIM | FLIP | mean / Cycles |\n|---|---|---|---|---|---|")
    noisy = cycles_reference(scene, "one_bounce", args.samples // 4, 1, resolution, cache)
    row(f"Cycles, {args.samples // 4} samples, another seed (noise floor)", noisy.indirect, reference)
    method_rows("scene", settings, reference)
    for name in BLOCKS[args.scene]:
        scene.objects[name].hide_render = scene.objects[name].hide_viewport = True
    empty = cycles_reference(scene, "one_bounce", args.samples, 0, resolution, cache)
    method_rows("blocks hidden", settings, empty)
    for name in BLOCKS[args.scene]:
        scene.objects[name].hide_render = scene.objects[name].hide_viewport = False
    lpv_alone_rows(settings.with_changes(indirect_method="lpv"))


if __name__ == "__main__":
    main()
