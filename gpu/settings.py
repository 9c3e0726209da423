"""Every parameter of the pipeline: its default, its valid range and what it means.

This is the one source of truth: Blender properties, command-line flags and benchmark
sweeps are generated from `PARAMETERS` or checked against it; the viewport overlays and
debug passes, which change what is shown but rerun no stage, and the viewport's convergence,
from `DISPLAY_PARAMETERS`;
the comparison with Cycles from `COMPARISON_PARAMETERS`; the corrections toward Cycles from
`CORRECTION_PARAMETERS`. `ALL_PARAMETERS` is every one a Blender property mirrors (all but
`COMMAND_LINE_ONLY`). `PRESETS` are named sets of pipeline parameters.
"""
from dataclasses import dataclass, field, fields, replace

from .errors import LPVError

METHODS = ("cm", "dpm", "wdpm", "tdpm", "twdpm", "auto")
INDIRECT_METHODS = ("lpv", "light_grid", "vpl_gather")
SLICE_AXES = ("x", "y", "z")
EMITTER_LIGHTS = ("grid", "brute_force")
EMITTER_INTERPOLATIONS = ("trilinear", "tricubic", "supersampled")


def _param(default, description, minimum=None, maximum=None, choices=None, expert=False):
    """A parameter's field; `expert` marks one an artist should not need to change (an
    internal of a stage, or a switch for tests and references): docs/settings.md marks it."""
    return field(default=default, metadata={
        "description": description, "min": minimum, "max": maximum, "choices": choices, "expert": expert})


class Validated:
    """A frozen dataclass of `_param` fields that validates itself when constructed."""

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            meta = f.metadata
            if meta["choices"] is not None:
                if value not in meta["choices"]:
                    raise LPVError(f"Setting '{f.name}' is {value!r}; choose one of {', '.join(meta['choices'])}.")
                continue
            kind = f.type if isinstance(f.type, type) else {"int": int, "float": float, "bool": bool}[f.type]
            if kind is bool:
                if not isinstance(value, bool):
                    raise LPVError(f"Setting '{f.name}' must be true or false, not {value!r}.")
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float)) or (kind is int and value != int(value)):
                raise LPVError(f"Setting '{f.name}' must be a {kind.__name__}, not {value!r}.")
            if not (meta["min"] <= value <= meta["max"]) or value != value:
                raise LPVError(
                    f"Setting '{f.name}' is {value}; it must lie between {meta['min']} and {meta['max']}.")
            object.__setattr__(self, f.name, kind(value))

    def with_changes(self, **changes):
        """A validated copy with some parameters changed."""
        unknown = set(changes) - {f.name for f in fields(self)}
        if unknown:
            known = ", ".join(f.name for f in fields(self))
            raise LPVError(f"Unknown setting '{sorted(unknown)[0]}'; known settings are {known}.")
        return replace(self, **changes)


AUTO_CONVERGED_RESOLUTION = 32
"""The light grid's cells a side in the sets a converging frame averages, on a GPU, when
converged_lpv_resolution is 0 (automatic)."""


@dataclass(frozen=True)
class Settings(Validated):
    """All pipeline parameters; constructing one validates it."""

    method: str = _param("cm", "How omnidirectional reflective shadow maps are made", choices=METHODS)
    rsm_resolution: int = _param(512, "Texels along one side of each RSM face", 16, 2048)
    vpls_per_light: int = _param(2048, "Virtual point lights sampled per light", 1, 65536)
    indirect_method: str = _param("light_grid", "How the VPLs' light reaches the surfaces: a light propagation volume "
                                         "(lpv), a light grid that gathers every VPL's light with visibility "
                                         "(light_grid), or every pixel gathering it with visibility (vpl_gather)",
                                  choices=INDIRECT_METHODS)
    lpv_resolution: int = _param(16, "Cells along each side of each grid of the indirect light", 4, 128)
    converged_lpv_resolution: int = _param(0, "Cells along each side of the light grid's grids in the VPL sets a "
                                              "frame averages beyond its first (a still viewport, a render of more "
                                              "than one set): the first frame after an edit keeps lpv_resolution, "
                                              "for speed; never coarser than it (0: 32 on a GPU, lpv_resolution on "
                                              "a software rasterizer, which gathers 32³ several times slower)",
                                           0, 128)
    grid_levels: int = _param(3, "Most nested grid levels around what the camera sees, each twice the size of "
                                 "the one before (cascades)", 1, 4, expert=True)
    propagation_iterations: int = _param(8, "Propagation steps through the volume", 1, 64)
    warp_alpha: float = _param(0.7, "WDPM step damping per iteration while the error exceeds a texel", 0.05, 1.0,
                               expert=True)
    tessellated_warp_alpha: float = _param(0.9, "TWDPM step damping per iteration (the thesis: 0.9)", 0.05, 1.0,
                                           expert=True)
    tessellation_unit: float = _param(0.1, "TDPM map length per tessellated segment (thesis eq. 8-9)", 0.005, 2.0,
                                      expert=True)
    warp_iterations: int = _param(16, "Most fixed-point iterations per texel of the warp", 1, 64, expert=True)
    warp_significant_figures: int = _param(2, "Significant figures of the warp's approximate-error stop", 1, 6,
                                           expert=True)
    occlusion: bool = _param(True, "Block propagation with the geometry volume")
    grid_phases: int = _param(2, "Light grids half a cell apart whose indirect light is averaged: the picture "
                                 "depends less on where cell boundaries fall", 1, 2, expert=True)
    grid_shift: float = _param(0.0, "Shift of the light grid against the scene, in cells along every axis "
                                    "(the picture should not depend on it: for invariance tests)", 0.0, 1.0,
                                expert=True)
    emission_samples: int = _param(4096, "Points sampled on emissive surfaces, in proportion to their power, whose "
                                         "light every pixel gathers as direct light", 16, 1048576)
    world_samples: int = _param(256, "Directions drawn from the world, in proportion to its light, whose light "
                                      "every pixel gathers with visibility and which bounces (0: the world lights "
                                      "nothing, it is only seen)", 0, 1048576)
    emitter_light: str = _param("grid", "How point emitters (emissive particles and instances, point lights beyond "
                                        "the light-map budget) light the pixels: through the emitter grid's 3D "
                                        "textures (grid) or every pixel summing every emitter (brute_force, the "
                                        "reference)", choices=EMITTER_LIGHTS, expert=True)
    emitter_interpolation: str = _param("supersampled", "How the emitter grid is read at a pixel: trilinear, tricubic "
                                                    "(Catmull-Rom) or super-sampled (eight trilinear reads)",
                                        choices=EMITTER_INTERPOLATIONS, expert=True)
    emitter_shadows: bool = _param(True, "Shade the point emitters' light by what stands between: the ratio of a "
                                         "light grid's irradiance with visibility to without, at every pixel")
    emitter_grid_resolution: int = _param(32, "Cells along each side of the emitter grid (rounded up to a power of "
                                              "two)", 8, 256, expert=True)
    emitter_bounce_samples: int = _param(2048, "Points on the surfaces that the emitters light (and their light "
                                               "bounces from) for the indirect light", 16, 65536)
    light_map_budget: int = _param(3, "Point lights that get light maps (the strongest at the view): the others "
                                      "light through the emitter grid, shadowed only as coarsely as emitter_shadows "
                                      "shades it", 0, 4096)
    light_cutoff: float = _param(0.001, "Share of the light at the view that the weakest lights and emitters may "
                                        "give together and be skipped (bounded by intensity over distance²)",
                                 0.0, 0.5, expert=True)
    bounces: int = _param(0, "Diffuse bounces of the indirect light at most, within the scene's Light Paths "
                             "(Cycles' Diffuse and Max Bounces); 0: as many as the Light Paths say (1 for a scene "
                             "that says nothing). Above 1, each later bounce is lit on points of the surfaces by "
                             "the one before (light grid and VPL gathering)", 0, 8)
    singularity_bound: float = _param(1.0, "How far a VPL's 1/r² is bounded next to it, in the area the VPL stands "
                                           "for over pi: added to r² for the lights' VPLs in the pixel gather (1: as "
                                           "a disk of that area lights its axis; the n-th VPL set of a converging "
                                           "frame takes 1/n of it), r² held at least there elsewhere (1: within that "
                                           "disk's radius its exitance; the light grid's clusters of emitters "
                                           "with a normal are squares of their area and take none); 0: unbounded, "
                                           "exact on average but spiky",
                                      0.0, 16.0, expert=True)
    converge_sets: int = _param(1, "VPL sets a rendered frame averages, each another Poisson pattern over the "
                                   "light maps seen through another point of the pixels: its light converges "
                                   "toward every texel's and its edges are anti-aliased (1: one sample at each "
                                   "pixel's centre)", 1, 4096)
    converge_seconds: float = _param(0.0, "Seconds a rendered frame goes on averaging VPL sets; above zero it "
                                          "replaces converge_sets", 0.0, 3600.0)
    indirect_intensity: float = _param(1.0, "Scale of the indirect light", 0.0, 100.0)
    shadow_bias: float = _param(1.5, "Shadow-map normal offset in texels", 0.0, 16.0)
    shadow_taps: int = _param(32, "Taps of a soft shadow's filter (PCSS: lights with a size); its blocker search "
                                  "takes half. Each VPL set turns them anew, so a converging frame averages the "
                                  "noise away", 4, 64)
    sun_cascade_resolution: int = _param(1024, "Texels along one side of each map of a sun's cascade: the maps of "
                                               "its direct light fitted to what the camera sees, nearer ones finer",
                                         16, 4096)
    width: int = _param(640, "Image width in pixels", 1, 16384)
    height: int = _param(480, "Image height in pixels", 1, 16384)

    def refined(self, software):
        """The settings of the VPL sets a frame averages beyond its first: the light grid
        at converged_lpv_resolution (docs/method.md, "Convergence"); `software`: whether
        the GL driver is a software rasterizer."""
        resolution = self.converged_lpv_resolution or (self.lpv_resolution if software else AUTO_CONVERGED_RESOLUTION)
        if self.indirect_method != "light_grid" or resolution <= self.lpv_resolution:
            return self
        return self.with_changes(lpv_resolution=resolution)


@dataclass(frozen=True)
class DisplaySettings(Validated):
    """What the viewport overlays and the debug render passes show, and how long a still
    viewport goes on converging."""

    show_vpls: bool = _param(False, "Draw every VPL as a point coloured by its flux")
    vpl_point_size: float = _param(4.0, "Size of the VPL points (overlay) and splats (pass) in pixels", 1.0, 32.0)
    show_lpv_slice: bool = _param(False, "Draw a slice through the light propagation volume, coloured by the "
                                         "light passing through each cell")
    lpv_slice_axis: str = _param("z", "Axis the LPV slice is perpendicular to", choices=SLICE_AXES)
    lpv_slice_position: float = _param(0.5, "Where the LPV slice lies along its axis, from the volume's low side "
                                            "(0) to its high side (1)", 0.0, 1.0)
    show_warp_status: bool = _param(False, "Show the warp status map of the first warped light in a corner of "
                                           "the view (green converged, yellow approximate, red failed)")
    viewport_vpl_sets: int = _param(64, "VPL sets a still viewport averages, one more each redraw, so its "
                                        "indirect light converges; any change starts again (1: no averaging)",
                                    1, 4096)
    debug_passes: bool = _param(False, "Write the VPL Splats and Warp Status passes in renders")


@dataclass(frozen=True)
class ComparisonSettings(Validated):
    """What the comparison with Cycles renders: the RSM and indirect methods ticked, the
    references' samples, the noise floor and the peers."""

    compare_cm: bool = _param(True, "Compare CM with Cycles")
    compare_dpm: bool = _param(False, "Compare DPM with Cycles")
    compare_wdpm: bool = _param(True, "Compare WDPM with Cycles")
    compare_tdpm: bool = _param(False, "Compare TDPM with Cycles")
    compare_twdpm: bool = _param(False, "Compare TWDPM with Cycles")
    compare_auto: bool = _param(False, "Compare AUTO with Cycles")
    compare_lpv: bool = _param(True, "Compare the light propagation volume (indirect method lpv) with Cycles")
    compare_light_grid: bool = _param(True, "Compare the light grid (indirect method light_grid) with Cycles")
    compare_vpl_gather: bool = _param(True, "Compare the per-pixel VPL gather (indirect method vpl_gather) with "
                                            "Cycles")
    compare_samples: int = _param(256, "Cycles samples per pixel of each reference", 1, 65536)
    compare_noise_floor: bool = _param(True, "Render each reference again with another seed to measure its noise")
    compare_peers: bool = _param(True, "Also render what a user might pick instead: EEVEE with ray tracing (the "
                                       "scene's EEVEE settings; minutes without a GPU) and Cycles at 1 and 4 samples "
                                       "denoised by OpenImageDenoise")

    @property
    def methods(self):
        return [method for method in METHODS if getattr(self, f"compare_{method}")]

    @property
    def indirect_methods(self):
        return [method for method in INDIRECT_METHODS if getattr(self, f"compare_{method}")]


@dataclass(frozen=True)
class CorrectionSettings(Validated):
    """How long a render is corrected toward Cycles and by how many local sample workers
    (corrections/corrector.py)."""

    correct_seconds: float = _param(0.0, "Seconds a rendered frame is corrected toward Cycles' full global "
                                         "illumination by Cycles samples of its view, after the preview (0: not "
                                         "corrected)", 0.0, 3600.0)
    correction_workers: int = _param(2, "Cycles sample worker processes started on this machine for the "
                                        "corrections, one CPU core each", 1, 256)
    viewport_corrections: bool = _param(False, "Correct the still viewport toward Cycles: sample workers start, "
                                               "and each redraw shows what their samples corrected")
    correction_viewport_width: int = _param(320, "Width in pixels the viewport is rendered at while it is corrected "
                                                 "(Cycles' samples are the cost), drawn over the whole view",
                                            16, 16384)


PARAMETERS = {f.name: f for f in fields(Settings)}
DISPLAY_PARAMETERS = {f.name: f for f in fields(DisplaySettings)}
COMPARISON_PARAMETERS = {f.name: f for f in fields(ComparisonSettings)}
CORRECTION_PARAMETERS = {f.name: f for f in fields(CorrectionSettings)}
COMMAND_LINE_ONLY = ("correct_seconds",)
"""Parameters of the command line's renders alone: F12 runs inside Blender, whose Python
cannot start the sample workers (docs/method.md, "Corrections toward Cycles")."""
ALL_PARAMETERS = {**PARAMETERS, **DISPLAY_PARAMETERS, **COMPARISON_PARAMETERS,
                  **{name: f for name, f in CORRECTION_PARAMETERS.items() if name not in COMMAND_LINE_ONLY}}


PRESETS = {
    "fast": {"method": "auto", "rsm_resolution": 256, "vpls_per_light": 65536, "indirect_method": "light_grid",
             "lpv_resolution": 16, "converge_sets": 1},
    "balanced": {"method": "auto", "rsm_resolution": 256, "vpls_per_light": 2048, "indirect_method": "light_grid",
                 "lpv_resolution": 32, "converge_sets": 1},
    "accurate": {"method": "auto", "rsm_resolution": 256, "vpls_per_light": 2048, "indirect_method": "vpl_gather",
                 "lpv_resolution": 32, "converge_sets": 1},
}
"""Named quality levels, each a set of Settings values: what `choose_presets` (bench/
sweep_report.py) picked from the Pareto front of the `fronts` sweep on the H100, by the
viewport's redraws after camera moves and light edits against the error from Cycles
(docs/benchmarks.md, "Presets"); a parameter the preset's indirect method does not read
is left out. The panel's buttons and the command line's --preset apply them; other
settings keep their values."""
INDIRECT_METHOD_ONLY = {"propagation_iterations": "lpv", "occlusion": "lpv"}
"""Parameters only one indirect method reads, and that method."""
PRESET_PARAMETERS = ("method", "rsm_resolution", "vpls_per_light", "indirect_method", "lpv_resolution",
                     "propagation_iterations", "converge_sets")


def preset_settings(name, **changes):
    """Settings of the preset `name` (None: the defaults), with `changes` (given flags,
    the image size) on top."""
    if name is None:
        return Settings(**changes)
    if name not in PRESETS:
        raise LPVError(f"There is no preset '{name}'; choose one of {', '.join(PRESETS)}.")
    return Settings(**{**PRESETS[name], **changes})


def describe_preset(name):
    """A preset's values in a few words, like 'WDPM, RSM 512², 2048 VPLs, LPV 16³, 8 steps',
    'AUTO, RSM 256², 2048 VPLs, light grid 32³' or 'AUTO, RSM 256², 2048 VPLs, VPL gather
    (grids 32³), 8 VPL sets'."""
    s = preset_settings(name)
    words = f"{s.method.upper()}, RSM {s.rsm_resolution}², {s.vpls_per_light} VPLs, "
    words += {"lpv": f"LPV {s.lpv_resolution}³, {s.propagation_iterations} steps",
              "light_grid": f"light grid {s.lpv_resolution}³",
              "vpl_gather": f"VPL gather (grids {s.lpv_resolution}³)"}[s.indirect_method]
    return words + (f", {s.converge_sets} VPL sets" if s.converge_sets > 1 else "")


def matching_preset(settings):
    """The preset whose every value `settings` has, or None (custom settings)."""
    return next((name for name, values in PRESETS.items()
                 if all(getattr(settings, key) == value for key, value in values.items())), None)
