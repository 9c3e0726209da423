"""Prints a SHA-256 digest of every pass the demo scenes render with each indirect method,
so that a change meant to leave the images alone can show it did.

    LP_NUM_THREADS=1 python scripts/image_digests.py [--out digests.json] [--width 320 --height 180]

renders each demo scene (built with bpy) with the light grid, VPL gathering and the LPV,
and the first two again with four bounces and with four VPL sets averaged, and prints
one line a frame: scene, variant, and a digest of each pass's float32 bytes. Run it
before and after a change and compare the JSON files. On llvmpipe, one thread
(LP_NUM_THREADS=1): with more, the order of its atomic additions varies from run to run,
and so do the last bits of the city's light grid and the particles' direct light.
"""
import argparse
import hashlib
import json

from lpv_preview import demo
from lpv_preview.gpu.passes import PASS_NAMES
from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.settings import INDIRECT_METHODS, Settings

parser = argparse.ArgumentParser(description="digests of the demo scenes' passes, per indirect method")
parser.add_argument("--out", help="also write the digests to this JSON file")
parser.add_argument("--width", type=int, default=320)
parser.add_argument("--height", type=int, default=180)
args = parser.parse_args()

variants = {method: {"indirect_method": method} for method in INDIRECT_METHODS}
variants.update({f"{method}, 4 bounces": {"indirect_method": method, "bounces": 4}
                 for method in INDIRECT_METHODS if method != "lpv"})
variants.update({f"{method}, 4 sets": {"indirect_method": method, "converge_sets": 4}
                 for method in INDIRECT_METHODS if method != "lpv"})
digests = {}
for name in demo.SCENES:
    scene = demo.extracted(name, resolution=(args.width, args.height))
    for variant, changes in variants.items():
        frame = render_once(scene, Settings(width=args.width, height=args.height, **changes), passes=PASS_NAMES)
        digests[f"{name}: {variant}"] = {pass_name: hashlib.sha256(image.astype("float32").tobytes()).hexdigest()
                                         for pass_name, image in frame.passes.items()}
        line = "  ".join(f"{pass_name} {digest[:12]}" for pass_name, digest in digests[f"{name}: {variant}"].items())
        print(f"{name:9} {variant:24} {line}", flush=True)
if args.out:
    with open(args.out, "w") as file:
        json.dump(digests, file, indent=1)
