"""The flags the commands share, and what they give, checked before any work: the setting
flags generated from gpu/settings.py, the corrections' flags, an output folder that can be
written, a frame range. Scripts and tests build their parsers from these too."""
import argparse
import os
import tempfile

from ..corrections.sample_workers import check_scheduler
from ..gpu.errors import LPVError
from ..gpu.passes import render_passes
from ..gpu.settings import (CORRECTION_PARAMETERS, DISPLAY_PARAMETERS, INDIRECT_METHODS, METHODS, PARAMETERS, PRESETS,
                            CorrectionSettings, describe_preset, preset_settings)


def positive_int(text):
    """An argparse type: a whole number of at least 1."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number of at least 1")
    return value


def method_list(text, known=METHODS):
    """An argparse type: comma-separated methods of gpu/settings.py, at least one."""
    methods = [method.strip() for method in text.split(",") if method.strip()]
    unknown = [method for method in methods if method not in known]
    if unknown or not methods:
        raise argparse.ArgumentTypeError(f"unknown or no method '{','.join(unknown)}'; choose from "
                                         f"{', '.join(known)}")
    return methods


def lower_first(text):
    """A sentence's first letter in lower case, its names (EEVEE) kept, to follow 'do not'."""
    return text[:1].lower() + text[1:]


def indirect_method_list(text):
    """An argparse type: comma-separated indirect methods of gpu/settings.py, at least one."""
    return method_list(text, INDIRECT_METHODS)


SCENE_SIZE = {"width": "the scene's render resolution", "height": "the scene's render resolution"}
"""What --width and --height default to where a command takes the image size from the
scene (demo, render, compare): gpu/settings.py's 640×480 would mislead there."""


def add_setting_flags(parser, size_defaults=None):
    """One flag per parameter of gpu/settings.py, defaulting to None (= not given), and
    --preset, whose values the flags given override. `size_defaults` ({"width": text,
    "height": text}) says what the image size is when not given, where that is not the
    parameter's default (SCENE_SIZE)."""
    parser.add_argument("--preset", choices=tuple(PRESETS), help="start from this preset of gpu/settings.py: "
                        + "; ".join(f"{name}: {describe_preset(name)}" for name in PRESETS))
    for name, field in PARAMETERS.items():
        add_parameter_flag(parser, name, field, default_text=(size_defaults or {}).get(name))


def add_parameter_flag(parser, name, field, flag=None, default_text=None):
    """The flag of one parameter of gpu/settings.py (`flag`: its name, else the parameter's
    with dashes), defaulting to None (= not given), its range and default in its help
    (`default_text`: what it is when not given, where not the parameter's default)."""
    meta = field.metadata
    flag = flag or "--" + name.replace("_", "-")
    if field.type in (bool, "bool"):
        parser.add_argument(flag, dest=name, action=argparse.BooleanOptionalAction, default=None,
                            help=meta["description"])
        return
    kind = {"int": int, "float": float, "str": str}.get(field.type, field.type)
    default = f"default: {default_text}" if default_text else f"default {field.default}"
    limits = f" ({meta['min']}..{meta['max']}, {default})" if meta["min"] is not None else ""
    parser.add_argument(flag, dest=name, type=kind, default=None, choices=meta["choices"],
                        help=meta["description"] + limits)


def add_debug_passes_flag(parser):
    debug = ", ".join(p.name for p in render_passes(debug=True) if p.debug)
    parser.add_argument("--debug-passes", action="store_true",
                        help=f"{DISPLAY_PARAMETERS['debug_passes'].metadata['description']} (EXR layers {debug})")


def add_correction_flags(parser, scheduler=True):
    """--correct-seconds and --workers (gpu/settings.py CorrectionSettings), and --scheduler
    where the .blend can be shared."""
    for name, flag in (("correct_seconds", "--correct-seconds"), ("correction_workers", "--workers")):
        add_parameter_flag(parser, name, CORRECTION_PARAMETERS[name], flag)
    if scheduler:
        parser.add_argument("--scheduler", help="with --correct-seconds: the tls://HOST:PORT of a Dask scheduler "
                                                "whose workers render the Cycles samples, its certificates in Dask's "
                                                "configuration (README), instead of local workers")


def correction_from(args):
    """The CorrectionSettings the flags give, refused before any work when bad."""
    scheduler = getattr(args, "scheduler", None)
    given = {name: getattr(args, name) for name in ("correct_seconds", "correction_workers")
             if getattr(args, name) is not None}
    correction = CorrectionSettings(**given)
    if scheduler is not None:
        if correction.correct_seconds <= 0:
            raise LPVError("--scheduler is for the corrections; give --correct-seconds too.")
        if "correction_workers" in given:
            raise LPVError("--workers starts local workers and --scheduler uses a cluster's; give one of them.")
        check_scheduler(scheduler)
    return correction


def settings_from(args, width, height):
    """The settings the flags give (over the preset, if any), `width` x `height` unless given."""
    given = {name: getattr(args, name) for name in PARAMETERS if getattr(args, name) is not None}
    given.setdefault("width", width)
    given.setdefault("height", height)
    return preset_settings(args.preset, **given)


def check_setting_flags(args):
    """Refuse bad setting flags before any work, though the image size may yet come from
    the scene."""
    settings_from(args, PARAMETERS["width"].default, PARAMETERS["height"].default)


def check_writable(folder):
    """Refuse an output folder that cannot be made or written into, before any work: make
    what is missing of it, write a probe file, and remove both again."""
    folder = os.path.abspath(folder)
    made = []  # the folders missing now, the outermost first
    missing = folder
    while not os.path.exists(missing):
        made.insert(0, missing)
        missing = os.path.dirname(missing)
    try:
        os.makedirs(folder, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as error:
        raise LPVError(f"Cannot write into the output folder '{folder}' ({error.strerror}); "
                       f"choose a writable folder.") from None
    finally:
        for path in reversed(made):
            if os.path.isdir(path):
                os.rmdir(path)


def settings_for_blend(bpy_scene, args):
    """The flags' settings, the image size from the .blend's render resolution unless given."""
    from ..addon.extract import render_resolution
    return settings_from(args, *render_resolution(bpy_scene))


def pass_names(args):
    """The pipeline passes a command writes: ours, and the debug ones with --debug-passes."""
    return tuple(p.name for p in render_passes(args.debug_passes))


def parse_frames(text):
    """'7' or '1-24' as a range of frame numbers."""
    first, _, last = text.partition("-")
    try:
        first, last = int(first), int(last or first)
    except ValueError:
        raise LPVError(f"--frames '{text}' is not a frame or a range; write it like 7 or 1-24.") from None
    if last < first:
        raise LPVError(f"--frames '{text}' ends before it starts; write the first frame first, like 1-24.")
    return range(first, last + 1)


def command_line(args):
    return "python -m lpv_preview " + " ".join(args.argv)
