"""Ground-truth images from real Cycles, to measure LPV Preview against.

Cycles renders a temporary linked copy of the scene (its settings are the copy's own, its
objects, world and camera the scene's) on the CPU from its camera into a multilayer EXR
in a temporary folder, read back with OpenImageIO (cycles_render.py). The user's scene
is never changed. A render goes in parts of its samples (`cycles_passes_in_parts`) so
that it can be stopped.

`cycles_reference` makes the references the preview is judged by. The main one, "f12",
is Cycles' Combined pass as F12 renders the scene with its own settings (bounces, world,
glossy, transmission, film, pixel filter, view layer), only its samples (plain ones: no
adaptive sampling, time limit or denoiser, which change the noise, not the image), seed
and size replaced. Two diffuse ones tell where an error comes from: one diffuse bounce
(the light transport an LPV approximates) and full global illumination, each split into
diffuse direct and diffuse indirect light (Cycles' light passes times its colour pass),
with their Combined pass beside them. Each is cached in a `ReferenceCache` (which holds
the peers' renders too, addon/peers.py) under a key of what F12 renders
(addon/render_signature.py) and the reference's own settings.
"""
import hashlib
import json
import os
import re
from contextlib import contextmanager
from dataclasses import dataclass

import bpy
import numpy as np

from ..gpu.errors import LPVError
from ..gpu.passes import COMPARED_PASS_NAMES
from ..gpu.temporary_folders import temporary_folder
from .cycles_render import (PASS_BY_NAME, REFERENCE_BOUNCES, REFERENCE_FILTER_WIDTH, apply_f12_settings,
                            apply_render_settings, enable_cycles, read_exr_passes, render_to_file, settings_in_use,
                            view_layer_to_render)
from .render_scene import scene_and_signature_to_render

F12 = "f12"
"""The main reference's kind: Cycles' Combined as F12 renders it."""
REFERENCE_KINDS = (F12, *REFERENCE_BOUNCES)
"""Every reference kind: F12's, then the diffuse ones (one bounce, full GI)."""


@contextmanager
def temporary_copy(scene):
    """A linked copy of `scene` (the same objects, world, camera, frame and view layers)
    that a reference may set up freely, removed afterwards, also when the render fails:
    the user's scene is never changed. (Changing its settings and setting them back is
    not enough: switching the output to OpenEXR sets the image settings' linear colour
    space, which cannot be set back to unset.)"""
    copy = scene.copy()
    try:
        yield copy
    finally:
        bpy.data.scenes.remove(copy)


def render_cycles_passes(scene, passes=("Combined", "DiffDir", "DiffCol"), samples=64, resolution=None,
                         seed=0, max_bounces=None, light_threshold=0.0, pixel_filter_width=None):
    """Render `passes` of `scene` with Cycles on the CPU, as linear float32 (H, W, 3) RGB arrays.

    Row 0 is the top of the picture, as Blender's Image Editor shows it: world +X of a
    camera with no roll is to the right and its up direction is at the top.

    Pass names are Blender's short names (`COLOUR_PASSES`: "Combined", "DiffDir", "DiffCol",
    ...) or a layer name as Cycles writes it in a multilayer EXR ("Diffuse Direct", an AOV);
    the short names also switch their pass on. A pass without R, G and B channels in the
    rendered file raises LPVError naming it.

    `resolution` is (width, height) at 100 %, or None for the scene's own size and
    percentage; `max_bounces`, when given, caps every bounce type (0: direct light only);
    `pixel_filter_width` in pixels, None keeps the scene's. Denoising, adaptive sampling,
    clamping, the compositor and the sequencer are off, so the passes are raw Cycles.

    Returns {pass name: array, ..., "settings": dict of what was really used}; see
    `describe_reference_settings`. The render is of a copy of the scene
    (`temporary_copy`): the scene itself is left as it is. It goes in parts
    (`cycles_passes_in_parts`), so Ctrl-C stops it within about `PART_SECONDS`.
    """
    return run_to_end(cycles_passes_in_parts(scene, passes, samples, resolution, seed, max_bounces,
                                             light_threshold, pixel_filter_width))


PART_SECONDS = 1.5
"""About how long each part of a Cycles render spends sampling. Blender's render call
cannot be stopped from Python, so a render is split into consecutive subsets of its
samples (Cycles' sample subsets, whose mean weighted by their sample counts is the whole
render): Ctrl-C, Esc or closing the generator stop it after the part under way."""
PART_GROWTH = 4
"""How many times longer than the last a part may be: a part's time is mostly the scene's
synchronisation (a world's importance map) until its samples are long enough to time."""


def cycles_passes_in_parts(scene, passes=("Combined", "DiffDir", "DiffCol"), samples=64, resolution=None,
                           seed=0, max_bounces=None, light_threshold=0.0, pixel_filter_width=None):
    """`render_cycles_passes` one part at a time: a generator that yields (samples done,
    Cycles' seconds so far) after each part and returns what `render_cycles_passes` does.

    The first part is one sample, which times the render; each next part is as many
    samples as the last part's pace fits in `PART_SECONDS` (the last up to half as many
    more). Between parts nothing of the render is left in the scene, the file or the
    temporary folder.
    """
    def set_up(copy, view_layer, exr_path, sample_range):
        apply_render_settings(copy, view_layer, exr_path, passes, samples, sample_range, resolution, seed,
                              max_bounces, light_threshold, pixel_filter_width, False)
    return (yield from _render_in_parts(scene, passes, samples, set_up))


def f12_combined_in_parts(scene, samples, resolution, seed=0):
    """Cycles' Combined pass of `scene` as F12 renders it (`apply_f12_settings`: the
    scene's own settings) at `samples` plain samples with `seed` and `resolution`, as
    `cycles_passes_in_parts` renders in parts; returns {"Combined": array, "settings": dict}."""
    def set_up(copy, view_layer, exr_path, sample_range):
        apply_f12_settings(copy, view_layer, exr_path, samples, sample_range, resolution, seed)
    return (yield from _render_in_parts(scene, ("Combined",), samples, set_up))


def _render_in_parts(scene, passes, samples, set_up):
    """The parts of a render of `passes` at `samples`, each of a copy of the scene that
    `set_up(copy, view layer, exr path, sample range)` sets up (`cycles_passes_in_parts`).

    A part's seconds are taken as a fixed cost (the first part's, of one sample) plus its
    samples' own; each next part is as many samples as the longest part so far says fit
    in `PART_SECONDS`, at most `PART_GROWTH` times the last."""
    enable_cycles()
    sums, settings, seconds, done, length = {}, None, 0.0, 0, 1
    first_seconds, longest = None, (1, 0.0)  # (samples, seconds) of the longest part
    while done < samples:
        left = samples - done
        length = left if left < 1.5 * length else length  # no short part at the end
        sample_range = (done, length)
        images = _render_copy(scene, passes, lambda copy, view_layer, path: set_up(copy, view_layer, path,
                                                                                   sample_range))
        part_settings = images.pop("settings")
        for name, image in images.items():
            sums[name] = sums.get(name, 0.0) + image.astype(np.float64) * length
        settings = settings or part_settings
        seconds += part_settings["render_seconds"]
        done += length
        yield done, seconds
        if first_seconds is None:
            first_seconds = part_settings["render_seconds"]
        if length >= longest[0]:
            longest = (length, part_settings["render_seconds"])
        sample_seconds = (longest[1] - first_seconds) / (longest[0] - 1) if longest[0] > 1 else 0.0
        grown = PART_GROWTH * length
        length = max(1, min(int(PART_SECONDS / sample_seconds), grown) if sample_seconds > 0.0 else grown)
    images = {name: (total / samples).astype(np.float32) for name, total in sums.items()}
    return {**images, "settings": {**settings, "render_seconds": seconds}}


def run_to_end(steps, log=None):
    """Run a generator of steps to the end, handing each step to `log` when given; returns
    what the generator returns."""
    while True:
        try:
            step = next(steps)
        except StopIteration as finished:
            return finished.value
        if log is not None:
            log(step)


def render_cycles_denoised(scene, samples, resolution, seed, max_bounces=None, pixel_filter_width=None, as_f12=True):
    """Cycles' Combined pass at `samples`, denoised by OpenImageDenoise with the scene's
    viewport denoising settings (input passes, prefilter, quality), as its viewport shows
    that many samples; in one part, since the denoiser must see the whole render. With
    `as_f12`, as F12 renders it (`f12_combined_in_parts`), else as `render_cycles_passes`
    with `max_bounces` and `pixel_filter_width`; returns {"Combined": array, "settings": dict}."""
    enable_cycles()
    import _cycles  # on the path once Cycles is enabled
    if not _cycles.with_openimagedenoise:
        raise LPVError("This Blender's Cycles was built without OpenImageDenoise, so it has no denoised render to "
                       "compare; use an official Blender build.")

    def set_up(copy, view_layer, exr_path):
        if as_f12:
            apply_f12_settings(copy, view_layer, exr_path, samples, (0, samples), resolution, seed, denoise=True)
        else:
            apply_render_settings(copy, view_layer, exr_path, ("Combined",), samples, (0, samples), resolution, seed,
                                  max_bounces, 0.0, pixel_filter_width, True)
    return _render_copy(scene, ("Combined",), set_up)


def _render_copy(scene, passes, set_up):
    """`passes` of a render of a temporary copy of `scene` that `set_up(copy, view layer,
    exr path)` sets up."""
    view_layer_name = view_layer_to_render(scene).name
    wanted_layers = {name: PASS_BY_NAME[name].exr_layer if name in PASS_BY_NAME else name for name in passes}
    with temporary_folder() as folder, temporary_copy(scene) as copy:
        view_layer = copy.view_layers[view_layer_name]
        exr_path = os.path.join(folder, "cycles_reference.exr")
        set_up(copy, view_layer, exr_path)
        settings = settings_in_use(copy, view_layer)
        settings["render_seconds"] = render_to_file(copy, exr_path)
        images = read_exr_passes(exr_path, view_layer_name, wanted_layers)
    return {**images, "settings": settings}


def describe_reference_settings(settings):
    """One line saying how a reference was rendered, for reports and the UI."""
    width, height = settings["resolution"]
    return (f"Cycles {settings['device']}, {settings['samples']} samples, seed {settings['seed']}, "
            f"{width}x{height}, max bounces {settings['max_bounces']} (diffuse {settings['diffuse_bounces']}), "
            f"clamping {settings['clamp_direct']:g} / {settings['clamp_indirect']:g}, "
            f"light threshold {settings['light_threshold']:g}, {settings['pixel_filter']} filter "
            f"{settings['pixel_filter_width']:g} px, {settings['denoiser'] or 'no denoising'}, "
            f"rendered in {settings['render_seconds']:.2f} s")


# ----------------------------------------------------------------------------- references

REFERENCE_PASSES = ("DiffDir", "DiffInd", "DiffCol", "Combined")


@dataclass
class CyclesReference:
    """A diffuse reference: diffuse direct and indirect light and the Combined pass of the
    same render (its bounces and pixel filter: what the sample workers match), (H, W, 3)
    linear float32 top row first, and how it was rendered (`render_cycles_passes`' settings)."""

    kind: str
    direct: np.ndarray
    indirect: np.ndarray
    combined_pass: np.ndarray
    settings: dict
    compared_images = COMPARED_PASS_NAMES
    """The images of ours it measures."""

    @property
    def combined(self):
        """Diffuse direct plus indirect: the diffuse light alone (no glossy, emission or
        world seen directly), to tell the preview's diffuse errors from the rest."""
        return self.direct + self.indirect


@dataclass
class F12Reference:
    """Cycles' Combined pass as F12 renders the scene (`f12_combined_in_parts`), (H, W, 3)
    linear float32 top row first, and how it was rendered."""

    combined: np.ndarray
    settings: dict
    kind = F12
    compared_images = ("combined",)
    """The images of ours it measures: the whole picture alone, F12's having no split."""


ADDON_PACKAGE = __package__.rpartition(".")[0]
"""The add-on's package: 'bl_ext.<repository>.lpv_preview' when Blender installed it as an
extension, 'lpv_preview' on the command line and in the tests."""


def default_cache_folder():
    """$LPV_PREVIEW_CACHE; else, installed as an extension, the extension's own user folder
    ("cycles" in it: the extensions platform asks an extension to keep its files there);
    else $XDG_CACHE_HOME/lpv_preview/cycles or ~/.cache/lpv_preview/cycles."""
    if os.environ.get("LPV_PREVIEW_CACHE"):
        return os.environ["LPV_PREVIEW_CACHE"]
    try:
        return bpy.utils.extension_path_user(ADDON_PACKAGE, path="cycles")
    except ValueError:  # not an extension
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        return os.path.join(base, "lpv_preview", "cycles")


CACHE_FILE = re.compile(r"[0-9a-f]{20}\.npz(\.partial\.npz)?")
"""The name of a cached reference (its key) or of one being written: the cache's own files."""


class ReferenceCache:
    """Cycles references on disk, one .npz per key, so none is rendered twice."""

    def __init__(self, folder=None):
        self.folder = folder or default_cache_folder()

    def path(self, key):
        return os.path.join(self.folder, f"{key}.npz")

    def files(self):
        """The paths of the cache's own files; other files in its folder are not its."""
        try:
            names = os.listdir(self.folder)
        except OSError:
            return []
        return [os.path.join(self.folder, name) for name in sorted(names) if CACHE_FILE.fullmatch(name)]

    def size(self):
        """How many references the cache holds and their bytes on disk."""
        files = self.files()
        return sum(not path.endswith(".partial.npz") for path in files), sum(_file_size(path) for path in files)

    def empty(self):
        """Delete the cache's files (the next comparison renders its references again)."""
        for path in self.files():
            try:
                os.remove(path)
            except FileNotFoundError:
                pass
            except OSError as error:
                raise LPVError(f"Cannot delete the cached reference '{path}' ({error.strerror}); "
                               f"check the permissions of '{self.folder}'.") from None

    def describe(self):
        """The cache in a few words, like '3 Cycles references, 12.5 MB'."""
        count, size = self.size()
        return f"{count} Cycles reference{'' if count == 1 else 's'}, {size_text(size)}"

    def holds(self, key):
        """Whether a render is stored under `key` (keys differ per kind and format)."""
        try:
            with np.load(self.path(key)) as data:
                return bool(data.files)
        except (OSError, ValueError):
            return False

    def load(self, key):
        """The CyclesReference or F12Reference stored under `key`, or None."""
        data = self.load_arrays(key)
        try:
            if data is None:
                return None
            if str(data["kind"]) == F12:
                return F12Reference(data["combined"], data["settings"])
            return CyclesReference(str(data["kind"]), data["direct"], data["indirect"], data["combined_pass"],
                                   data["settings"])
        except KeyError:
            return None

    def store(self, key, reference):
        if isinstance(reference, F12Reference):
            arrays = {"kind": F12, "combined": reference.combined}
        else:
            arrays = {"kind": reference.kind, "direct": reference.direct, "indirect": reference.indirect,
                      "combined_pass": reference.combined_pass}
        self.store_arrays(key, arrays, reference.settings)

    def load_arrays(self, key):
        """{name: array, "settings": dict} stored under `key`, or None."""
        try:
            with np.load(self.path(key)) as data:
                return {**{name: data[name] for name in data.files}, "settings": json.loads(str(data["settings"]))}
        except (OSError, KeyError, ValueError):
            return None

    def store_arrays(self, key, arrays, settings):
        """Write `arrays` and `settings` (JSON) under a temporary name, renamed when complete
        (removed when interrupted); a cache that cannot be written only costs a render later."""
        partial = self.path(key) + ".partial.npz"
        try:
            os.makedirs(self.folder, exist_ok=True)
            np.savez_compressed(partial, settings=json.dumps(settings), **arrays)
            os.replace(partial, self.path(key))
        except OSError:
            pass
        finally:
            if os.path.exists(partial):
                os.remove(partial)


def _file_size(path):
    try:
        return os.path.getsize(path)
    except OSError:  # deleted meanwhile
        return 0


def size_text(size):
    """Bytes in a unit a person reads at a glance: '812 B', '12.5 MB'."""
    for unit in ("B", "kB", "MB", "GB"):
        if size < 1000 or unit == "GB":
            return f"{size:.0f} {unit}" if unit == "B" else f"{size:.1f} {unit}"
        size /= 1000


CACHE_FORMAT = 2
"""The version of what the cache stores: a key of another format never matches."""


def reference_key(signature, kind, samples, seed, resolution):
    """The cache key of a `kind` reference of what F12 renders (`signature`,
    addon/render_signature.py) with its own settings."""
    own = () if kind == F12 else (REFERENCE_BOUNCES[kind], REFERENCE_FILTER_WIDTH)
    return cache_key(signature, kind, samples, seed, tuple(resolution), *own)


def cache_key(signature, *settings):
    """The cache key of a render of what F12 renders (`signature`) with `settings`, in
    this Blender version and cache format."""
    parts = [signature, *settings, bpy.app.version_string, CACHE_FORMAT]
    return hashlib.sha1(repr(parts).encode()).hexdigest()[:20]


def cycles_reference(scene, kind, samples, seed=0, resolution=None, cache=None, signature=None):
    """The `kind` reference (`REFERENCE_KINDS`) of `scene` from its camera at `resolution`
    (None: the scene's render size), from `cache` when it holds one. `signature` is what
    F12 renders (render_scene.py `scene_and_signature_to_render`), when the caller has it."""
    return run_to_end(cycles_reference_in_parts(scene, kind, samples, seed, resolution, cache, signature))


def cycles_reference_in_parts(scene, kind, samples, seed=0, resolution=None, cache=None, signature=None):
    """`cycles_reference` as a generator: it yields nothing when the cache holds the
    reference, else (samples done, seconds so far) after each part of the render
    (`cycles_passes_in_parts`); it returns the F12Reference or CyclesReference."""
    if kind not in REFERENCE_KINDS:
        raise LPVError(f"Unknown Cycles reference '{kind}'; choose one of {', '.join(REFERENCE_KINDS)}.")
    from .extract import render_resolution
    resolution = tuple(resolution or render_resolution(scene))
    if signature is None:
        signature = scene_and_signature_to_render(scene, resolution)[1]
    key = reference_key(signature, kind, samples, seed, resolution)
    if cache is not None:
        cached = cache.load(key)
        if cached is not None:
            cached.settings["cached"] = True
            return cached
    if kind == F12:
        images = yield from f12_combined_in_parts(scene, samples, resolution, seed)
        reference = F12Reference(images["Combined"], {**images["settings"], "cached": False, "key": key})
    else:
        images = yield from cycles_passes_in_parts(scene, REFERENCE_PASSES, samples, resolution, seed,
                                                   REFERENCE_BOUNCES[kind], pixel_filter_width=REFERENCE_FILTER_WIDTH)
        colour = images["DiffCol"]
        reference = CyclesReference(kind, images["DiffDir"] * colour, images["DiffInd"] * colour, images["Combined"],
                                    {**images["settings"], "cached": False, "key": key})
    if cache is not None:
        cache.store(key, reference)
    return reference
