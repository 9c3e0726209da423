"""Panels: the pipeline's settings in the Render properties (when LPV Preview is the
engine) and in a "LPV Preview" tab of the 3D view's sidebar, with the last frame's
statistics. Which setting goes in which group is checked against gpu/settings.py."""
import bpy

from ..gpu.settings import ALL_PARAMETERS, PRESETS, matching_preset
from ..gpu.metrics import figure_text
from ..gpu.pipeline import STAGES as PIPELINE_STAGES
from .comparison import last_comparison, reference_label, row_label
from .cycles_reference import F12
from .cycles_reference import ReferenceCache
from .engine import ENGINE_ID
from .frame_stats import last_stats, missing_images_warning, renderer_warning
from .properties import settings_from_properties

SETTING_GROUPS = {
    "Method": ("method", "rsm_resolution", "vpls_per_light"),
    "World": ("world_samples",),
    "Emitters": ("emission_samples", "emitter_light", "emitter_interpolation", "emitter_grid_resolution",
                 "emitter_shadows", "emitter_bounce_samples", "light_map_budget", "light_cutoff"),
    "Indirect Light": ("indirect_method", "lpv_resolution", "grid_levels", "propagation_iterations", "occlusion",
                       "bounces", "singularity_bound", "indirect_intensity", "grid_phases", "grid_shift"),
    "Shadows": ("shadow_bias", "shadow_taps", "sun_cascade_resolution"),
    "Convergence": ("viewport_vpl_sets", "converge_sets", "converge_seconds", "converged_lpv_resolution"),
    "Warping": ("warp_alpha", "warp_iterations", "warp_significant_figures"),
    "Tessellation": ("tessellation_unit", "tessellated_warp_alpha"),
    "Overlays": ("show_vpls", "vpl_point_size", "show_lpv_slice", "lpv_slice_axis", "lpv_slice_position",
                 "show_warp_status"),
    "Passes": ("debug_passes",),
    "Corrections": ("viewport_corrections", "correction_viewport_width", "correction_workers"),
    "Comparison": ("compare_cm", "compare_dpm", "compare_wdpm", "compare_tdpm", "compare_twdpm", "compare_auto",
                   "compare_lpv", "compare_light_grid", "compare_vpl_gather", "compare_samples", "compare_noise_floor",
                   "compare_peers"),
}
ENABLED_BY = {"lpv_slice_axis": "show_lpv_slice", "lpv_slice_position": "show_lpv_slice",
              "correction_viewport_width": "viewport_corrections"}
"""Settings that matter only while another is on: drawn inactive while it is off."""
FROM_BLENDER = ("width", "height")
"""Settings Blender supplies: the render resolution, or the viewport's size."""

STAGES = (("extract_ms", "Extract"), *((key, label[0].upper() + label[1:]) for key, label in PIPELINE_STAGES.items()),
          ("debug_ms", "Debug passes"), ("readback_ms", "Readback"), ("total_ms", "Total"),
          ("converge_ms", "All VPL sets"))


def draw_presets(layout, properties):
    """One button per preset, the one the settings match pressed."""
    current = matching_preset(settings_from_properties(properties))
    row = layout.row(align=True)
    for name in PRESETS:
        row.operator(PRESET_OPERATOR, text=name.capitalize(), depress=name == current).preset = name


def draw_settings(layout, properties, group):
    if group == "Method":
        draw_presets(layout, properties)
    layout.use_property_split = True
    layout.use_property_decorate = False
    for name in SETTING_GROUPS[group]:
        row = layout.row()
        row.active = name not in ENABLED_BY or getattr(properties, ENABLED_BY[name])
        row.prop(properties, name)


def renderer_lines(stats):
    """The statistics panel's lines (text, icon) on the OpenGL renderer: its name, and a
    warning when it is a software rasterizer."""
    if "renderer" not in stats:
        return []
    warning = renderer_warning(stats)
    return [(f"Renderer: {stats['renderer']}", "NONE")] + ([(warning, "ERROR")] if warning else [])


def draw_statistics(layout, stats):
    if not stats:
        layout.label(text="Render a frame to see its statistics")
        return
    column = layout.column(align=True)
    for text, icon in renderer_lines(stats):
        column.label(text=text, icon=icon)
    for key, label in STAGES:  # the GPU's time where the driver times it (docs/performance.md)
        if key in stats:
            row = column.row()
            row.label(text=label)
            row.label(text=f"{stats.get('gpu_' + key, stats[key]):.1f} ms")
    column.separator()
    column.label(text=f"{stats.get('vpl_count', 0):,} VPLs, {stats.get('triangles', 0):,} triangles")
    if stats.get("vpl_sets", 1) > 1:
        column.label(text=f"Converging: {stats['vpl_sets']} VPL sets, {stats['accumulated_vpls']:,} VPLs averaged")
    if stats.get("lights_as_emitters") or stats.get("point_emitters") or stats.get("skipped_lights"):
        column.label(text=f"Lights: {stats['mapped_lights']} with maps, {stats['lights_as_emitters']} through the "
                          f"emitter grid, {stats['skipped_lights']} skipped")
        column.label(text=f"{stats['point_emitters']:,} point emitters, {stats['skipped_emitters']:,} skipped")
    if stats.get("rooms"):
        column.label(text=f"Rooms: {stats['rooms']} closed meshes holding a lamp, each lit by its own lights alone")
    methods = stats.get("light_methods")
    if methods:
        column.label(text="Methods: " + ", ".join(m.upper() for m in methods))
    status = stats.get("warp_status")
    if status:
        found = max(1, status["converged"] + status["approximate"] + status["failed"])
        column.label(text="Warp: " + ", ".join(f"{name} {status[name] / found:.1%}"
                                                for name in ("converged", "approximate", "failed")))
    if "correction_samples" in stats:
        column.label(text=f"Corrections: {stats['correction_samples']:,} Cycles samples, "
                          f"{stats['correction_samples_per_second']:,.0f} a second")
        if "correction_estimated_error" in stats:
            column.label(text=f"Estimated error (relative MSE): {stats['correction_estimated_error']:.4f}")
    if stats.get("correction_problem"):
        column.label(text=stats["correction_problem"], icon="ERROR")
    images = stats.get("images")
    if images:
        column.label(text=f"Images: {len(images)}")
    missing = missing_images_warning(stats)
    if missing:
        column.label(text=missing, icon="ERROR")
    approximated = stats.get("approximated_materials")
    if approximated:
        column.label(text="Approximated materials (a name alone: colour from nodes not evaluated):", icon="ERROR")
        for name in approximated:
            column.label(text=f"    {name}")


COMPARE_OPERATOR = "lpv_preview.compare_with_cycles"  # operators/compare.py
EMPTY_CACHE_OPERATOR = "lpv_preview.empty_cycles_cache"  # operators/cache.py
PRESET_OPERATOR = "lpv_preview.apply_preset"  # operators/presets.py


PANEL_FIGURES = (("psnr", "PSNR", ".1f"), ("relative_mse", "relMSE", ".3f"), ("ssim", "SSIM", ".3f"),
                 ("flip", "FLIP", ".3f"), ("mse", "MSE", ".2g"))
"""The figures of the panel's table; the relative ones are dashes against a black reference."""


def draw_comparison(layout, properties):
    """The comparison settings, its button, the reference cache's size with a button that
    empties it, and the last comparison's tables: per reference and image it measures, a
    row per method and peer that has the image; F12's first, then under a heading the
    diagnostic ones against Cycles' diffuse light (no denoised Cycles: it has none)."""
    draw_settings(layout, properties, "Comparison")
    layout.operator(COMPARE_OPERATOR, icon="RENDER_STILL")
    row = layout.row()
    row.label(text=f"Cache: {ReferenceCache().describe()}")
    row.operator(EMPTY_CACHE_OPERATOR, text="", icon="TRASH")
    comparison = last_comparison()
    if comparison is None:
        return
    rows = comparison.table()
    diagnostic_heading = False
    for kind, reference in comparison.references.items():
        if kind != F12 and not diagnostic_heading:
            layout.label(text="Diagnostic: against Cycles' diffuse light alone", icon="INFO")
            diagnostic_heading = True
        for image in reference.compared_images:
            box = layout.box()
            what = "F12 (its own settings)" if kind == F12 else f"diffuse {reference_label(kind)}"
            box.label(text=f"{image.capitalize()} vs Cycles {what}: {comparison.samples} samples, "
                           f"{reference.settings['render_seconds']:.1f} s")
            headings = ("Method", "ms", *(label for _, label, _ in PANEL_FIGURES))
            grid = box.grid_flow(columns=len(headings), row_major=True, even_columns=False, align=True)
            for heading in headings:
                grid.label(text=heading)
            for row in rows:
                if row["reference"] != kind or (row[f"{image}_mse"] is None and "missing" not in row):
                    continue
                figures = [figure_text(row[f"{image}_{metric}"], fmt) for metric, _, fmt in PANEL_FIGURES]
                for text in (row_label(row), "" if row["ms"] is None else f"{row['ms']:.0f}", *figures):
                    grid.label(text=text)
    layout.label(text="Images: \"LPV Compare ...\" in the Image Editor")


class LPVPreviewPanel:
    """Shown only while LPV Preview is the render engine."""

    COMPAT_ENGINES = {ENGINE_ID}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class RenderPropertiesPanel(LPVPreviewPanel):
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"


class GroupPanel(RenderPropertiesPanel):
    """A sub-panel of one group of settings."""

    group = ""
    bl_parent_id = "RENDER_PT_lpv_preview"

    def draw(self, context):
        draw_settings(self.layout, context.scene.lpv_preview, self.group)


class RENDER_PT_lpv_preview(RenderPropertiesPanel, bpy.types.Panel):
    bl_label = "LPV Preview"

    def draw(self, context):
        draw_settings(self.layout, context.scene.lpv_preview, "Method")


GROUP_PANELS = tuple(
    type(f"RENDER_PT_lpv_preview_{group.lower().replace(' ', '_')}", (GroupPanel, bpy.types.Panel),
         {"bl_label": group, "group": group})
    for group in list(SETTING_GROUPS)[1:] if group != "Comparison")


class RENDER_PT_lpv_preview_comparison(RenderPropertiesPanel, bpy.types.Panel):
    bl_label = "Compare with Cycles"
    bl_parent_id = "RENDER_PT_lpv_preview"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        draw_comparison(self.layout, context.scene.lpv_preview)


class RENDER_PT_lpv_preview_statistics(RenderPropertiesPanel, bpy.types.Panel):
    bl_label = "Statistics"
    bl_parent_id = "RENDER_PT_lpv_preview"

    def draw(self, context):
        draw_statistics(self.layout, last_stats())


class VIEW3D_PT_lpv_preview(LPVPreviewPanel, bpy.types.Panel):
    """The sidebar tab: every group and the statistics in one place."""

    bl_label = "LPV Preview"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "LPV Preview"

    def draw(self, context):
        for group in SETTING_GROUPS:
            box = self.layout.box()
            box.label(text=group)
            if group == "Comparison":
                draw_comparison(box, context.scene.lpv_preview)
            else:
                draw_settings(box, context.scene.lpv_preview, group)
        box = self.layout.box()
        box.label(text="Statistics")
        draw_statistics(box, last_stats())


CLASSES = (RENDER_PT_lpv_preview, *GROUP_PANELS, RENDER_PT_lpv_preview_comparison, RENDER_PT_lpv_preview_statistics,
           VIEW3D_PT_lpv_preview)


def check_groups():
    """Every setting of gpu/settings.py is in exactly one group or comes from Blender."""
    grouped = [name for names in SETTING_GROUPS.values() for name in names] + list(FROM_BLENDER)
    return sorted(grouped) == sorted(ALL_PARAMETERS) and len(grouped) == len(set(grouped))


register, unregister = bpy.utils.register_classes_factory(CLASSES)
