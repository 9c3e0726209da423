"""Command line: `python -m lpv_preview demo | render FILE.blend | export SCENE`.

`demo` builds a built-in scene with bpy and renders it; `render` renders a user's .blend
from its active camera; `export` saves a demo scene as .npz for machines without Blender.
Each writes a multi-layer EXR (combined, direct, indirect), tone-mapped PNGs of combined
and indirect, and stats.json. Errors a user can fix print one line, no traceback.
"""
import argparse
import json
import os
import sys
import time

from .gpu.errors import LPVError
from .gpu.settings import PARAMETERS, Settings

SCENE_SIZE_FLAGS = ("width", "height")  # taken from the .blend unless given


def add_setting_flags(parser):
    """One flag per parameter of gpu/settings.py, defaulting to None (= not given)."""
    for name, field in PARAMETERS.items():
        meta = field.metadata
        flag = "--" + name.replace("_", "-")
        if field.type in (bool, "bool"):
            parser.add_argument(flag, action=argparse.BooleanOptionalAction, default=None, help=meta["description"])
            continue
        kind = {"int": int, "float": float, "str": str}.get(field.type, field.type)
        limits = f" ({meta['min']}..{meta['max']}, default {field.default})" if meta["min"] is not None else ""
        parser.add_argument(flag, type=kind, default=None, choices=meta["choices"],
                            help=meta["description"] + limits)


def settings_from(args, width, height):
    given = {name: getattr(args, name) for name in PARAMETERS if getattr(args, name) is not None}
    given.setdefault("width", width)
    given.setdefault("height", height)
    return Settings(**given)


def write_outputs(frame, out_dir, extra_stats):
    """combined/direct/indirect EXR, PNGs of combined and indirect, stats.json."""
    from .gpu.image_io import write_exr, write_png
    write_exr(os.path.join(out_dir, "passes.exr"), frame.passes)
    write_png(os.path.join(out_dir, "combined.png"), frame.passes["combined"])
    write_png(os.path.join(out_dir, "indirect.png"), frame.passes["indirect"])
    stats = {**extra_stats, **frame.stats}
    with open(os.path.join(out_dir, "stats.json"), "w") as handle:
        json.dump(stats, handle, indent=2)
    return stats


def render_bpy_scene(bpy_scene, args, extra_stats):
    """Extract the evaluated scene, render it and write the outputs."""
    import bpy
    from .addon.extract import extract_scene, render_resolution
    from .gpu.pipeline import Pipeline
    start = time.perf_counter()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    width, height = render_resolution(bpy_scene)
    settings = settings_from(args, width, height)
    scene = extract_scene(depsgraph, resolution=(settings.width, settings.height))
    extract_ms = (time.perf_counter() - start) * 1000
    pipeline = Pipeline(settings)
    try:
        frame = pipeline.render(scene)
    finally:
        pipeline.release()
    return write_outputs(frame, args.out, {**extra_stats, "extract_ms": extract_ms})


def command_demo(args):
    from .demo import build
    start = time.perf_counter()
    bpy_scene = build(args.scene, **({"triangles": args.triangles} if args.triangles else {}))
    build_ms = (time.perf_counter() - start) * 1000
    stats = render_bpy_scene(bpy_scene, args, {"scene": args.scene, "build_ms": build_ms})
    stats["command_ms"] = (time.perf_counter() - start) * 1000
    return stats


def command_render(args):
    import bpy
    if not os.path.isfile(args.file):
        raise LPVError(f"There is no file '{args.file}'; give the path of a .blend file.")
    start = time.perf_counter()
    try:
        bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.file))
    except RuntimeError as error:
        raise LPVError(f"Blender cannot open '{args.file}' ({str(error).strip()}); check that it is a .blend file.")
    stats = render_bpy_scene(bpy.context.scene, args, {"file": os.path.abspath(args.file)})
    stats["command_ms"] = (time.perf_counter() - start) * 1000
    return stats


def command_export(args):
    from .demo import export_npz
    scene = export_npz(args.scene, args.out, **({"triangles": args.triangles} if args.triangles else {}))
    return {"scene": args.scene, "file": args.out, "triangles": scene.triangle_count, "lights": len(scene.lights)}


def build_parser():
    parser = argparse.ArgumentParser(prog="python -m lpv_preview", description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    demo = commands.add_parser("demo", help="build a built-in scene with bpy and render it")
    demo.add_argument("--scene", default="cornell", choices=("cornell", "atrium", "city"))
    demo.add_argument("--triangles", type=int, help="triangle count of the atrium or the city")
    demo.add_argument("--out", default="out", help="output folder (default: out)")
    add_setting_flags(demo)
    demo.set_defaults(run=command_demo)
    render = commands.add_parser("render", help="render a .blend file from its active camera")
    render.add_argument("file")
    render.add_argument("--out", default="out", help="output folder (default: out)")
    add_setting_flags(render)
    render.set_defaults(run=command_render)
    export = commands.add_parser("export", help="save a demo scene as .npz for machines without Blender")
    export.add_argument("scene", choices=("cornell", "atrium", "city"))
    export.add_argument("--triangles", type=int, help="triangle count of the atrium or the city")
    export.add_argument("--out", required=True, help="the .npz file to write")
    export.set_defaults(run=command_export)
    return parser


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        result = args.run(args)
    except LPVError as error:
        print(f"lpv_preview: {error}", file=sys.stderr)
        return 2
    print(json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
