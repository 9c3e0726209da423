"""The commands that render: `demo`, `render`, `compare`, and `export` of a demo scene.
Each checks its flags before any work and hands the work to addon/ or demo/."""
import os
import sys
import time

from .. import demo
from ..gpu.errors import LPVError
from ..gpu.image_library import openimageio
from ..gpu.settings import ComparisonSettings
from .flags import check_setting_flags, check_writable, correction_from, parse_frames, pass_names, settings_for_blend


def command_demo(args):
    from ..addon.batch import render_to_files
    openimageio()  # the images are written at the end: refused before any work where they cannot be
    check_writable(args.out)
    check_setting_flags(args)
    correction = correction_from(args)
    start = time.perf_counter()
    bpy_scene = demo.build(args.scene, **({"triangles": args.triangles} if args.triangles is not None else {}))
    build_ms = (time.perf_counter() - start) * 1000
    stats = render_to_files(bpy_scene, settings_for_blend(bpy_scene, args), pass_names(args), args.out,
                            {"scene": args.scene, "build_ms": build_ms}, correction)
    stats["command_ms"] = (time.perf_counter() - start) * 1000
    return stats


def command_render(args):
    from ..addon.batch import open_blend, render_animation, render_to_files
    frames = parse_frames(args.frames) if args.frames else None
    openimageio()  # the images are written at the end: refused before any work where they cannot be
    check_writable(args.out)
    check_setting_flags(args)
    correction = correction_from(args)
    start = time.perf_counter()
    bpy_scene = open_blend(args.file)
    settings, file = settings_for_blend(bpy_scene, args), os.path.abspath(args.file)
    if frames is None:
        stats = render_to_files(bpy_scene, settings, pass_names(args), args.out, {"file": file}, correction, file,
                                args.scheduler)
    else:
        stats = {"file": file, **render_animation(bpy_scene, frames, settings, pass_names(args), args.out,
                                                  args.overwrite, correction, file, args.scheduler)}
    stats["command_ms"] = (time.perf_counter() - start) * 1000
    return stats


def check_methods_fit(bpy_scene, settings, methods, indirect_methods):
    """Refuse, before any Cycles reference is rendered, a comparison whose frames our
    renderer cannot make here (no OpenGL 4.5, too large for the driver or the memory), on
    the GL thread its frames render on (addon/comparison.py)."""
    from ..addon.render_scene import scene_to_render
    from ..gpu.capacity import check_frame_fits
    from ..gpu.context import GLContext
    from ..gpu.gl_thread import GLThread
    scene = scene_to_render(bpy_scene, (settings.width, settings.height))

    def check():
        for method in methods:
            for indirect in indirect_methods:
                check_frame_fits(GLContext.shared(), settings.with_changes(method=method, indirect_method=indirect),
                                 scene)
    GLThread.shared().call(check)


def command_compare(args):
    """Cycles references and each method's errors against them, written to args.out, the
    PNGs through the scene's colour management; every step, part of a Cycles render and
    the references' estimated time on stderr."""
    from ..addon.batch import open_blend
    from ..addon.comparison import comparison_steps, write_report
    from ..addon.cycles_reference import run_to_end
    from ..addon.cycles_reference import ReferenceCache
    from ..addon.view_transform import scene_view_transform
    openimageio()  # the images are written at the end: refused before any work where they cannot be
    check_writable(args.out)
    check_setting_flags(args)
    start = time.perf_counter()
    if args.file in demo.SCENES:
        bpy_scene = demo.build(args.file)
    elif not os.path.isfile(args.file):
        raise LPVError(f"There is no file '{args.file}'; give the path of a .blend file or a demo scene name "
                       f"({', '.join(demo.SCENES)}).")
    else:
        bpy_scene = open_blend(args.file)
    settings, view_transform = settings_for_blend(bpy_scene, args), scene_view_transform(bpy_scene)
    # --indirect-method alone compares that one; else the list (default every one).
    indirect_methods = args.indirect_methods or ([args.indirect_method] if args.indirect_method
                                                 else ComparisonSettings().indirect_methods)
    check_methods_fit(bpy_scene, settings, args.methods, indirect_methods)
    cache = None if args.no_cache else ReferenceCache(args.cache)
    steps = comparison_steps(bpy_scene, args.methods, args.samples, settings, cache,
                             noise_floor=not args.no_noise_floor, indirect_methods=indirect_methods,
                             peers=not args.no_peers)
    progress = lambda step: print(f"[{time.perf_counter() - start:5.0f} s {step[0]:4.0%}] {step[1]}", file=sys.stderr,
                                  flush=True)
    rows = write_report(run_to_end(steps, progress), args.out, view_transform)
    return {"rows": rows, "out": os.path.abspath(args.out), "command_ms": (time.perf_counter() - start) * 1000}


def command_export(args):
    from ..gpu.scene_file import cycles_reference_path
    if args.cycles_width and not args.cycles_samples:
        raise LPVError("--cycles-width needs --cycles-samples: the Cycles reference is rendered only when asked.")
    if not args.out.endswith(".npz"):  # NumPy would add the suffix, beside a folder or the path given
        example = os.path.join(args.out, f"{args.scene}.npz") if os.path.isdir(args.out) else f"{args.out}.npz"
        raise LPVError(f"--out '{args.out}' is not a .npz file's path; give one like {example}.")
    check_writable(os.path.dirname(args.out))
    options = {key: value for key, value in (("triangles", args.triangles), ("lights", args.lights),
                                             ("light_kind", args.light_kind), ("cycles_samples", args.cycles_samples),
                                             ("cycles_width", args.cycles_width)) if value is not None}
    scene = demo.export_npz(args.scene, args.out, **options)
    return {"scene": args.scene, "file": args.out, "triangles": scene.triangle_count, "lights": len(scene.lights),
            **({"cycles_reference": str(cycles_reference_path(args.out))} if args.cycles_samples else {})}


def software_renderer_warning():
    """The warning for this command's frames when the process's OpenGL context is a
    software rasterizer (addon/frame_stats.py), or None: no frame rendered, or on a GPU."""
    from ..addon.frame_stats import renderer_warning
    from ..gpu.context import GLContext
    glc = GLContext.last_made  # made by the first frame, on whichever thread; a refusal before it leaves None
    if glc is None:
        return None
    return renderer_warning({"renderer": glc.renderer, "software_renderer": glc.is_software})
