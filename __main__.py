"""Command line: `python -m lpv_preview demo | render FILE.blend | compare FILE.blend | export SCENE | bench`.

`demo` builds a built-in scene with bpy and renders it; `render` renders a user's .blend
from its active camera (`--frames 1-24`: an animation, one EXR a frame, resumable);
`compare` measures the methods and their peers (EEVEE, denoised Cycles) against Cycles
references; `export` saves a demo scene as .npz for machines without Blender; `bench`
measures every RSM method against CM (the thesis's Table 1), runs declared sweeps and
writes the benchmarks page.
Each render writes a multi-layer EXR (combined, direct, indirect), tone-mapped PNGs of
combined and indirect, and stats.json. Errors a user can fix print one line, no traceback,
and exit with status 2; Ctrl-C stops a command with one line and status 130; a command
whose frames a software rasterizer rendered warns of it in one line.

This file is the entry point only: the flags and the commands are in cli/, the work in
the packages they call; bpy and the GPU are imported by the commands that need them.
"""
import faulthandler
import json
import sys

from .cli.commands import software_renderer_warning
from .cli.parser import build_parser
from .gpu.errors import LPVError

STOPPED = "Stopped by Ctrl-C; temporary files were removed, finished frames and Cycles references are kept."


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser().parse_args(argv)
    args.argv = argv
    try:
        result = args.run(args)
    except LPVError as error:
        print(f"lpv_preview: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"\nlpv_preview: {STOPPED}", file=sys.stderr)
        return 130
    warning = software_renderer_warning()
    if warning:
        print(f"lpv_preview: warning: {warning}", file=sys.stderr)
    missing = result.get("missing_images_warning") if isinstance(result, dict) else None
    if missing:
        print(f"lpv_preview: warning: {missing}", file=sys.stderr)
    print(json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    faulthandler.enable()  # a crash in a library prints every thread's stack for a bug report
    sys.exit(main())
