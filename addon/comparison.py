"""LPV Preview against Cycles: the references, our pipeline per method, its peers, the errors.

`comparison_steps` does the work one step at a time (each part of a Cycles render, each
method, each peer), so the comparison operator can show progress and stop between steps
when the user presses Esc; the command line runs the same steps to the end and prints each
one. Errors are `gpu.metrics.image_errors` per RSM method and indirect method: the main
table's of our combined image against Cycles' Combined as F12 renders the scene (the F12
reference, cycles_reference.py), the diagnostic table's of our indirect and combined
images against Cycles' diffuse light alone (the one-bounce and full-GI references). The
peers a user would pick instead (addon/peers.py: EEVEE with ray tracing, Cycles at 1 and 4
samples with OpenImageDenoise) get the same figures, their Combined against F12's (EEVEE
also its diffuse light against the diffuse references); and each reference's own noise
floor is the same figures between two Cycles renders that differ only in the seed.
"""
import math
from dataclasses import dataclass, field

from ..gpu.errors import LPVError
from ..gpu.metrics import RELATIVE_EPSILON, error_map, figure_text, heat_map, image_errors
from ..gpu.passes import COMPARED_PASS_NAMES as IMAGES
from ..gpu.settings import INDIRECT_METHODS, METHODS
from .cycles_reference import F12, REFERENCE_KINDS, cycles_reference_in_parts, reference_key
from .cycles_render import REFERENCE_BOUNCES
from .peers import peer_renders
from .render_scene import scene_and_signature_to_render

_last = []  # the last comparison the operator finished, for the panel


def remember(comparison):
    _last[:] = [comparison]


def last_comparison():
    return _last[0] if _last else None


def forget():
    _last.clear()


@dataclass
class MethodResult:
    """One method's images (top row first), full-frame milliseconds (every stage redone,
    shaders warm) and errors: reference kind -> image -> metric -> value."""

    method: str
    indirect_method: str
    milliseconds: float
    images: dict
    errors: dict = field(default_factory=dict)
    vpl_sets: int = 1

    @property
    def label(self):
        """Like 'WDPM light grid' or 'WDPM vpl gather, 8 VPL sets'."""
        return method_label(self.method, self.indirect_method, self.vpl_sets)


def method_label(method, indirect_method, vpl_sets):
    return (f"{method.upper()} {indirect_method.replace('_', ' ')}" +
            (f", {vpl_sets} VPL sets" if vpl_sets > 1 else ""))


def reference_label(kind):
    """A reference kind as the reports name it: 'F12', 'one bounce', 'full gi'."""
    return "F12" if kind == F12 else kind.replace("_", " ")


@dataclass
class Comparison:
    references: dict = field(default_factory=dict)   # kind -> F12Reference or CyclesReference (seed 0)
    noise_floor: dict = field(default_factory=dict)  # kind -> image -> metric -> value (seed 1 against seed 0)
    methods: list = field(default_factory=list)      # MethodResult
    peers: list = field(default_factory=list)        # addon/peers.py PeerRender
    peer_errors: list = field(default_factory=list)  # per peer: kind -> image -> metric -> value
    samples: int = 0
    resolution: tuple = ()

    def heat_map(self, method_result, kind, image=None):
        """The relative error of a method's image (None: the first the reference measures:
        F12's combined, a diffuse reference's indirect) against a reference, as an sRGB
        heat map."""
        reference = self.references[kind]
        image = image or reference.compared_images[0]
        return heat_map(error_map(method_result.images[image], getattr(reference, image)))

    def table(self, kinds=None):
        """The rows of the comparison table per reference of `kinds` (None: all): our
        methods, the peers with images for it (one that could not render: in F12's table,
        with None figures), then the noise floor. Each row has the figures of the images
        its reference measures. "ms" is the row's own render time, "cycles_s" the
        reference's."""
        rows = []
        for kind, reference in self.references.items():
            if kinds is not None and kind not in kinds:
                continue
            images = reference.compared_images
            common = {"reference": kind, "cycles_s": reference.settings["render_seconds"]}
            for result in self.methods:
                rows.append({"method": result.method, "indirect_method": result.indirect_method,
                             "vpl_sets": result.vpl_sets, **common, "ms": result.milliseconds,
                             **_flat(result.errors[kind], images)})
            for peer, errors in zip(self.peers, self.peer_errors):
                if kind in errors or (peer.missing and kind == F12):
                    rows.append({"method": peer.name, "indirect_method": None, **common,
                                 "ms": None if peer.seconds is None else peer.seconds * 1000,
                                 **_flat(errors.get(kind, {}), images),
                                 **({"missing": peer.missing} if peer.missing else {})})
            if kind in self.noise_floor:
                rows.append({"method": "Cycles seed 1", "indirect_method": None, **common, "ms": None,
                             **_flat(self.noise_floor[kind], images)})
        return rows

    def main_table(self):
        """The rows against F12's Combined: what the comparison measures."""
        return self.table((F12,))

    def diffuse_table(self):
        """The rows against the diffuse references: where an error comes from."""
        return self.table(tuple(REFERENCE_BOUNCES))


def _flat(errors, images):
    """Every one of `images`' figures as columns; an image without figures has None in each."""
    return {f"{image}_{metric}": errors.get(image, {}).get(metric) for image in images
            for metric, _, _ in METRIC_COLUMNS}


def _errors(test, reference):
    """Figures of each image the `reference` measures that `test` ({name: image}) has."""
    return {image: image_errors(test[image], getattr(reference, image))
            for image in reference.compared_images if image in test}


def peer_errors(peer, references):
    """A peer's figures per reference kind: its images against F12's, its diffuse images
    against the diffuse references'."""
    return {kind: _errors(peer.images if kind == F12 else peer.diffuse_images, reference)
            for kind, reference in references.items() if (peer.images if kind == F12 else peer.diffuse_images)}


def full_frame(settings, lpv_scene):
    """A frame of `lpv_scene` with every stage redone and the shaders and Poisson cells
    of the first set already made (the time a settled preview takes for a full update),
    averaging the VPL sets the settings ask for (its stats' `converge_ms` is the time of
    them all), on the GL thread (gpu/gl_thread.py): never on Blender's."""
    from ..gpu.gl_thread import GLThread
    return GLThread.shared().call(_full_frame, settings, lpv_scene)


def _full_frame(settings, lpv_scene):
    from ..gpu.pipeline import Pipeline
    pipeline = Pipeline(settings)
    try:
        pipeline.render(lpv_scene)
        pipeline.invalidate()
        return pipeline.render_converged(lpv_scene)
    finally:
        pipeline.release()


def comparison_steps(scene, methods, samples, settings, cache=None, kinds=REFERENCE_KINDS,
                     noise_floor=True, indirect_methods=None, peers=False):
    """Compare `scene` (its camera, frame and `settings`' image size) rendered by each of
    `methods` with each of `indirect_methods` (None: the settings' own), and with `peers`
    its peers (addon/peers.py), with the `kinds` of Cycles reference at `samples` (F12's
    first, then the diffuse ones).

    A generator: it yields (fraction done, what it does) before each step, after each
    part of a Cycles render (its samples, seconds and the time left) and, once the first
    sample of the first reference to render is timed, how long all of them will take
    (`estimate_text`); it returns the Comparison. Every Cycles render is of a temporary
    copy of the scene, so closing the generator between steps leaves the scene as it was.
    """
    unknown = [m for m in methods if m not in METHODS]
    if unknown or not methods:
        raise LPVError(f"Unknown or no method '{','.join(unknown)}'; choose from {', '.join(METHODS)}.")
    indirect_methods = indirect_methods or [settings.indirect_method]
    unknown = [m for m in indirect_methods if m not in INDIRECT_METHODS]
    if unknown:
        raise LPVError(f"Unknown indirect method '{','.join(unknown)}'; choose from {', '.join(INDIRECT_METHODS)}.")
    resolution = (settings.width, settings.height)
    comparison = Comparison(samples=samples, resolution=resolution)
    lpv_scene, signature = scene_and_signature_to_render(scene, resolution)
    renders = [(kind, seed) for kind in kinds for seed in ((0, 1) if noise_floor else (0,))]
    to_render = [(kind, seed) for kind, seed in renders if cache is None
                 or not cache.holds(reference_key(signature, kind, samples, seed, resolution))]
    peer_steps = peer_renders(scene, resolution, signature, cache) if peers else []
    ours = [(method, indirect) for method in methods for indirect in indirect_methods]
    steps = len(renders) + len(peer_steps) + len(ours)
    for step, (kind, seed) in enumerate(renders):
        label = f"Cycles {reference_label(kind)} {'reference' if seed == 0 else 'noise floor (a second seed)'}"
        rendered = (kind, seed) in to_render
        yield step / steps, f"{label}: " + (f"{samples} samples at {resolution[0]}×{resolution[1]}" if rendered
                                            else "from the cache")
        parts = cycles_reference_in_parts(scene, kind, samples, seed, resolution, cache, signature)
        estimate_renders = len(to_render) if rendered and (kind, seed) == to_render[0] else 0
        reference = yield from _parts_as_steps(parts, label, comparison, step / steps, 1 / steps, estimate_renders)
        if seed == 0:
            comparison.references[kind] = reference
        else:
            comparison.noise_floor[kind] = _errors({image: getattr(reference, image)
                                                    for image in reference.compared_images},
                                                   comparison.references[kind])
    for index, (label, render) in enumerate(peer_steps):
        yield (len(renders) + index) / steps, label
        peer = render()
        comparison.peers.append(peer)
        comparison.peer_errors.append(peer_errors(peer, comparison.references))
    for index, (method, indirect) in enumerate(ours):
        result = MethodResult(method, indirect, 0.0, {})
        yield (len(renders) + len(peer_steps) + index) / steps, f"LPV Preview {result.label}"
        frame = full_frame(settings.with_changes(method=method, indirect_method=indirect), lpv_scene)
        result.milliseconds, result.vpl_sets = frame.stats["converge_ms"], frame.stats["vpl_sets"]
        result.images = {image: frame.passes[image] for image in IMAGES}
        for kind, reference in comparison.references.items():
            result.errors[kind] = _errors(result.images, reference)
        comparison.methods.append(result)
    return comparison


def _parts_as_steps(parts, label, comparison, start, share, estimate_renders):
    """A reference's render (`cycles_reference_in_parts`) as comparison steps: after each
    part, its samples, seconds and the time left; after the first, when
    `estimate_renders`, the estimate for that many renders. Returns the reference."""
    try:
        while True:
            try:
                done, seconds = next(parts)
            except StopIteration as finished:
                return finished.value
            samples = comparison.samples
            left = f"about {duration_text(seconds / done * (samples - done))} left" if done < samples else "done"
            yield start + share * done / samples, f"{label}: {done}/{samples} samples in {duration_text(seconds)}, {left}"
            if estimate_renders and done == 1:
                yield start + share / samples, estimate_text(estimate_renders, comparison, seconds)
    finally:
        parts.close()


def estimate_text(renders, comparison, first_sample_seconds):
    """How long `renders` Cycles references of the comparison's samples and size will
    take, from the time the first sample of the first one took (scene set-up included)."""
    width, height = comparison.resolution
    total = renders * comparison.samples * first_sample_seconds
    return (f"Cycles references: about {duration_text(total)} for {renders} render{'s' if renders > 1 else ''} of "
            f"{comparison.samples} samples at {width}×{height}, estimated from the {first_sample_seconds:.2f} s "
            f"the first sample took (more bounces take longer)")


def duration_text(seconds):
    """Seconds in a unit a person reads at a glance: '40 s', '12 min', '1.5 h'."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 90 * 60:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


METRIC_COLUMNS = (("psnr", "PSNR dB", ".2f"), ("relative_mse", "relMSE", ".4f"), ("ssim", "SSIM", ".4f"),
                  ("flip", "FLIP", ".4f"), ("mse", "MSE", ".3g"), ("mean", "mean", ".3g"),
                  ("reference_mean", "Cycles mean", ".3g"))


def row_label(row):
    """A table row's first cell: 'WDPM light grid', a peer's name (with why it is missing),
    'Cycles seed 1'."""
    if row["indirect_method"] is not None:
        return method_label(row["method"], row["indirect_method"], row["vpl_sets"])
    return row["method"] + (f" (missing: {row['missing']})" if "missing" in row else "")


def markdown_table(comparison):
    """The comparison's tables in Markdown: first, per method, peer and noise floor, the
    row's and Cycles' time and the combined image's errors and means against Cycles'
    Combined as F12 renders the scene; under it, the diagnostic table of the indirect and
    combined images against Cycles' diffuse light alone, per diffuse reference. An
    undefined figure is a dash."""
    text = ""
    main = comparison.main_table()
    if main:
        text += _markdown_rows(main, comparison.references[F12].compared_images, with_reference=False)
    diffuse = comparison.diffuse_table()
    if diffuse:
        text += ("\n## Diffuse light alone (diagnostic)\n\nThe same figures against Cycles' diffuse passes "
                 "(diffuse direct and indirect light, without glossy, emission or the world seen directly), with "
                 "one bounce and with full GI: where an error of the table above comes from.\n\n")
        text += _markdown_rows(diffuse, IMAGES, with_reference=True)
    return text


def _markdown_rows(rows, images, with_reference):
    head = ["method", *(["reference"] if with_reference else []), "ms", "Cycles s"] + [
        f"{image} {label}" for image in images for _, label, _ in METRIC_COLUMNS]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for row in rows:
        cells = [row_label(row), *([reference_label(row["reference"])] if with_reference else []),
                 "" if row["ms"] is None else f"{row['ms']:.1f}", f"{row['cycles_s']:.1f}"]
        cells += [figure_text(row[f"{image}_{metric}"], fmt) for image in images for metric, _, fmt in METRIC_COLUMNS]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


TABLE_LEGEND = (
    ("the table", "each row is measured against Cycles' Combined pass as F12 renders the scene with its own "
                  "settings (its bounces, world, glossy, transmission, emission, clamping, film, pixel filter and "
                  "view layer), only its samples (the comparison's, all of them: no adaptive sampling, time limit or "
                  "denoising, which change the noise, not the picture), seed and image size replaced; our combined "
                  "image, EEVEE's and denoised Cycles' Combined pass are measured against it"),
    ("the diagnostic table", "the same figures against Cycles' diffuse light alone (its Diffuse Direct and "
                             "Indirect passes times Diffuse Color, with a 0.01 px pixel filter) to tell where an "
                             "error comes from: our indirect and combined images, EEVEE's diffuse light"),
    ("method", "what made the row: our RSM method and indirect method (and the VPL sets it averages), a peer "
               "(EEVEE with ray tracing; Cycles at 1 or 4 samples denoised by OpenImageDenoise as F12 renders the "
               "scene, in the table only), or \"Cycles seed 1\": the reference rendered again with another seed, "
               "its own noise. A row whose figures are as good as that row's is as close to Cycles as the "
               "reference can tell"),
    ("reference", "in the diagnostic table, the diffuse reference the row is measured against: one bounce (light "
                  "that bounced off one surface at most) or full GI (up to "
                  f"{REFERENCE_BOUNCES['full_gi']} bounces)"),
    ("ms", "the row's render time in milliseconds (ours: every stage redone, shaders compiled; a peer: its "
           "wall time); lower is faster"),
    ("Cycles s", "the reference's render time in seconds"),
    ("indirect …, combined …", "the image measured: indirect is the light that bounced off a surface before "
                               "reaching the camera, combined is the whole image (direct plus indirect; in the "
                               "diagnostic table, Cycles' diffuse direct plus indirect)"),
    ("PSNR dB", "peak signal-to-noise ratio in decibels, the peak being the reference's brightest pixel; "
                "higher is better"),
    ("relMSE", f"relative mean squared error, mean of (ours − Cycles)² / (Cycles² + {RELATIVE_EPSILON}): errors in "
               "dark parts "
               "count as much as in bright ones; lower is better, 0 is identical"),
    ("SSIM", "structural similarity of the brightness, from −1 to 1: whether shapes and gradients match; higher "
             "is better, 1 is identical"),
    ("FLIP", "NVIDIA's perceptual difference (HDR-FLIP), from 0 to 1: how different the two look when flipped "
             "between; lower is better"),
    ("MSE", "mean squared error in the images' linear units; lower is better; defined when the reference is "
            "black"),
    ("mean, Cycles mean", "the average pixel value of the row's image and of the reference's: the closer the "
                          "two, the less the image is too dark or too bright"),
    ("—", "undefined: the reference is black there (a relative figure has no scale; MSE and the means say how "
          "far from black the row is), the images are identical (PSNR), or a peer has no such image"),
)
"""What each table measures, and each column (or group of them), what it is and which way
is better: written under the tables, so the report explains itself."""


def markdown_legend():
    """TABLE_LEGEND as a Markdown list under the heading "Legend"."""
    return "\n## Legend\n\n" + "".join(f"- **{column}**: {text}.\n" for column, text in TABLE_LEGEND)


def _json_number(value):
    """JSON has no infinity: an undefined figure (the infinite PSNR of identical images) is null."""
    return None if isinstance(value, float) and not math.isfinite(value) else value


def write_report(comparison, folder, view_transform=None):
    """comparison.json and comparison.md (the tables and their legend), PNGs of every
    reference, method and peer image through `view_transform` (gpu/colour_management.py
    ViewTransform: the scene's colour management, as F12 saves a PNG; None: the default,
    Blender's Standard view on sRGB), one for all so that they compare by eye, and
    false-colour heat maps of each method's error against each reference (F12's combined,
    a diffuse reference's indirect); returns the main table's rows."""
    import json
    import os
    import re

    from ..gpu.colour_management import ViewTransform
    from ..gpu.image_io import write_png
    view_transform = view_transform or ViewTransform()
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as error:
        raise LPVError(f"Cannot create the output folder '{folder}' ({error.strerror}); choose a writable folder.")
    for kind, reference in comparison.references.items():
        for image in reference.compared_images:
            write_png(os.path.join(folder, f"cycles_{kind}_{image}.png"), getattr(reference, image), view_transform)
    for result in comparison.methods:
        name = f"{result.method}_{result.indirect_method}"
        for image in IMAGES:
            write_png(os.path.join(folder, f"ours_{name}_{image}.png"), result.images[image], view_transform)
        for kind, reference in comparison.references.items():
            write_png(os.path.join(folder, f"error_{name}_{kind}_{reference.compared_images[0]}.png"),
                      comparison.heat_map(result, kind), view_transform=None)
    for peer in comparison.peers:
        name = re.sub(r"[^a-z0-9]+", "_", peer.name.lower()).strip("_")
        for image, pixels in peer.images.items():
            write_png(os.path.join(folder, f"peer_{name}_{image}.png"), pixels, view_transform)
        for image, pixels in peer.diffuse_images.items():
            write_png(os.path.join(folder, f"peer_{name}_diffuse_{image}.png"), pixels, view_transform)
    json_rows = lambda rows: [{key: _json_number(value) for key, value in row.items()} for row in rows]
    report = {"samples": comparison.samples, "resolution": list(comparison.resolution),
              "references": {kind: reference.settings for kind, reference in comparison.references.items()},
              "peers": [{"name": peer.name, **peer.settings} for peer in comparison.peers],
              "rows": json_rows(comparison.main_table()), "diffuse_rows": json_rows(comparison.diffuse_table())}
    with open(os.path.join(folder, "comparison.json"), "w") as handle:
        json.dump(report, handle, indent=2, default=float, allow_nan=False)
    with open(os.path.join(folder, "comparison.md"), "w") as handle:
        handle.write(markdown_table(comparison) + markdown_legend())
    return report["rows"]
