"""The command line's parser: each command's flags and the function that runs it."""
import argparse

from .. import demo
from ..gpu.scene_edits import LIGHT_KIND_NAMES
from ..gpu.settings import COMPARISON_PARAMETERS, ComparisonSettings
from .bench_command import add_bench_modes, command_bench
from .commands import command_compare, command_demo, command_export, command_render
from .flags import (SCENE_SIZE, add_correction_flags, add_debug_passes_flag, add_setting_flags,
                    indirect_method_list, lower_first, method_list, positive_int)

DESCRIPTION = ("Command line: `python -m lpv_preview demo | render FILE.blend | compare FILE.blend | export SCENE | "
               "bench`.")


def triangles_help():
    return "triangle count of " + " or ".join(f"the {name} ({low:,}..{high:,})"
                                              for name, (low, high) in demo.TRIANGLE_RANGES.items())


def add_demo_command(commands):
    """`demo`: build a built-in scene with bpy and render it."""
    command = commands.add_parser("demo", help="build a built-in scene with bpy and render it")
    command.add_argument("--scene", default=demo.SCENES[0], choices=demo.ALL_SCENES)
    command.add_argument("--triangles", type=int, help=triangles_help())
    command.add_argument("--out", default="out", help="output folder (default: out)")
    add_setting_flags(command, SCENE_SIZE)
    add_debug_passes_flag(command)
    add_correction_flags(command, scheduler=False)  # a demo scene is never saved where a cluster could read it
    command.set_defaults(run=command_demo)


def add_render_command(commands):
    """`render`: a .blend file from its active camera, a frame or an animation."""
    command = commands.add_parser("render", help="render a .blend file from its active camera")
    command.add_argument("file")
    command.add_argument("--out", default="out", help="output folder (default: out)")
    command.add_argument("--frames", help="render these frames, like 1-24, one EXR each (frame_0001.exr ...)")
    command.add_argument("--overwrite", action="store_true", help="with --frames: render frames already written too")
    add_setting_flags(command, SCENE_SIZE)
    add_debug_passes_flag(command)
    add_correction_flags(command)
    command.set_defaults(run=command_render)


def add_compare_command(commands):
    """`compare`: the methods and their peers against Cycles references."""
    comparison = ComparisonSettings()
    scene_list = ", ".join(demo.SCENES)
    command = commands.add_parser("compare", help="measure the methods and their peers (EEVEE, denoised Cycles) "
                                                  "against Cycles references")
    command.add_argument("file", help=f"a .blend file, or a demo scene name ({scene_list})")
    command.add_argument("--methods", type=method_list, default=comparison.methods,
                         help=f"comma-separated methods (default: {','.join(comparison.methods)})")
    command.add_argument("--samples", type=positive_int, default=comparison.compare_samples,
                         help=f"{COMPARISON_PARAMETERS['compare_samples'].metadata['description']} "
                              f"(default: {comparison.compare_samples})")
    command.add_argument("--out", default="out/compare", help="output folder (default: out/compare)")
    command.add_argument("--cache", help="folder of cached Cycles references (default: ~/.cache/lpv_preview/cycles)")
    command.add_argument("--no-cache", action="store_true", help="render the references even when cached")
    command.add_argument("--no-noise-floor", action="store_true",
                         help=f"do not {COMPARISON_PARAMETERS['compare_noise_floor'].metadata['description'].lower()}")
    command.add_argument("--indirect-methods", type=indirect_method_list,
                         help=f"comma-separated indirect methods, a row each per method (default: "
                              f"{','.join(comparison.indirect_methods)}; only --indirect-method's when that is given)")
    command.add_argument("--no-peers", action="store_true",
                         help="do not " + lower_first(COMPARISON_PARAMETERS["compare_peers"].metadata["description"]))
    add_setting_flags(command, SCENE_SIZE)
    command.set_defaults(run=command_compare)


def add_export_command(commands):
    """`export`: a demo scene as .npz for machines without Blender."""
    command = commands.add_parser("export", help="save a demo scene as .npz for machines without Blender")
    command.add_argument("scene", choices=demo.ALL_SCENES)
    command.add_argument("--triangles", type=int, help=triangles_help())
    command.add_argument("--out", required=True, help="the .npz file to write")
    command.add_argument("--lights", type=positive_int, help="replace the lights by this many of --light-kind")
    command.add_argument("--light-kind", choices=tuple(LIGHT_KIND_NAMES), default="point")
    command.add_argument("--cycles-samples", type=positive_int,
                         help="also store the Cycles one-bounce indirect image beside it (NAME.cycles.npz) for sweeps")
    command.add_argument("--cycles-width", type=positive_int, help="its width in pixels (default: the scene's)")
    command.set_defaults(run=command_export)


def add_bench_command(commands):
    """`bench`: Table 1, or the measurement of a BENCH_MODES flag."""
    from ..bench.table1 import BUDGETS, TABLE1_METHODS
    command = commands.add_parser("bench", help="every RSM method against CM: time, DPM and LPV quality")
    command.add_argument("--scenes", help=f"comma-separated demo scene names and/or .npz files (default: "
                                          f"{','.join(demo.LAMP_SCENES)}; with --artist, artist scenes, default all)")
    command.add_argument("--methods", type=method_list, default=list(TABLE1_METHODS),
                         help=f"comma-separated methods (default: {','.join(TABLE1_METHODS)})")
    command.add_argument("--budget", default=BUDGETS[0], choices=(*BUDGETS, "both"))
    command.add_argument("--frames", type=positive_int, default=5, help="camera-path frames for the LPV quality")
    command.add_argument("--repeats", type=positive_int, default=3, help="timed full frames per method (median)")
    command.add_argument("--out", default="out/bench", help="folder for table1.json and table1.md, or the sweep's files")
    command.add_argument("--sweeps", help="the file of declared sweeps (default: bench/sweeps.toml)")
    command.add_argument("--gpu-previews", help="with --corrections: the JSON of scripts/time_previews.py on a GPU "
                                               "(docs/bench/corrections_previews.json), to judge the goals also with "
                                               "the preview rendered there")
    command.add_argument("--emitters-up-to", type=int, default=10, choices=range(11), metavar="N",
                         help="largest emitter count's power of 4 for --emitters (default 10: 1,048,576)")
    command.add_argument("--samples", type=positive_int, help="with --artist: Cycles' samples of the reference")
    command.add_argument("--eevee-samples", type=positive_int,
                         help="with --artist: EEVEE's samples (default: the scene's own)")
    command.add_argument("--gpu-times", help="with --artist: the JSON of scripts/time_artist_scenes.py on a GPU, to "
                                             "judge the time goals")
    add_bench_modes(command)
    add_setting_flags(command, {"width": "960 for Table 1; a sweep's or measurement's own otherwise",
                                "height": "540 for Table 1; a sweep's or measurement's own otherwise"})
    command.set_defaults(run=command_bench)


def build_parser():
    parser = argparse.ArgumentParser(prog="python -m lpv_preview", description=DESCRIPTION)
    commands = parser.add_subparsers(dest="command", required=True)
    for add_command in (add_demo_command, add_render_command, add_compare_command, add_export_command,
                        add_bench_command):
        add_command(commands)
    return parser
