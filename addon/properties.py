"""The pipeline's and the overlays' settings as Blender properties, generated from
gpu/settings.py.

One property per parameter, with the same default, range and description, stored on the
scene as `scene.lpv_preview`.
"""
import bpy

from ..gpu.settings import (ALL_PARAMETERS, COMMAND_LINE_ONLY, COMPARISON_PARAMETERS, CORRECTION_PARAMETERS,
                            DISPLAY_PARAMETERS, PARAMETERS, ComparisonSettings, CorrectionSettings, DisplaySettings,
                            Settings)


def redraw_views(properties, context):
    """A setting changed: every 3D view draws again, and its engine reads the settings
    anew (from the original scene: Python property edits may not reach the evaluated one)."""
    screen = getattr(context, "screen", None)
    for area in screen.areas if screen is not None else ():
        if area.type == "VIEW_3D":
            area.tag_redraw()


def refresh_render_passes(properties, context):
    """"Debug passes" changed: every view layer of the scene registers its passes again
    (the engine's update_render_passes), as the Cycles add-on does for its passes, so
    the compositor and the EXR see the new set before the next render."""
    for view_layer in properties.id_data.view_layers:
        view_layer.update_render_passes()
    redraw_views(properties, context)


UPDATES = {"debug_passes": refresh_render_passes}
"""Settings whose change needs more than a redraw of the views."""


def _property(name, field):
    meta = field.metadata
    label = name.replace("_", " ").capitalize()
    common = {"name": label, "description": meta["description"], "default": field.default,
              "update": UPDATES.get(name, redraw_views)}
    if meta["choices"] is not None:
        items = [(choice, choice.upper(), "") for choice in meta["choices"]]
        return bpy.props.EnumProperty(items=items, **common)
    kind = {"bool": bool, "int": int, "float": float}.get(field.type, field.type)
    if kind is bool:
        return bpy.props.BoolProperty(**common)
    if kind is int:
        return bpy.props.IntProperty(min=meta["min"], max=meta["max"], **common)
    return bpy.props.FloatProperty(min=meta["min"], max=meta["max"], **common)


LPVPreviewSettings = type("LPVPreviewSettings", (bpy.types.PropertyGroup,), {
    "__annotations__": {name: _property(name, field) for name, field in ALL_PARAMETERS.items()},
    "__doc__": "LPV Preview settings of a scene (generated from gpu/settings.py)",
})


def _values(properties, names):
    """Blender keeps float properties in single precision; they are rounded back to the 7
    significant digits that holds, so 0.7 stays 0.7."""
    values = {name: getattr(properties, name) for name in names}
    return {name: float(f"{v:.7g}") if isinstance(v, float) else v for name, v in values.items()}


def settings_from_properties(properties, **overrides):
    """A validated Settings from a scene's properties."""
    return Settings(**{**_values(properties, PARAMETERS), **overrides})


def correction_settings_from_properties(properties):
    """A validated CorrectionSettings from a scene's properties (the command line's own at their defaults)."""
    return CorrectionSettings(**_values(properties, (name for name in CORRECTION_PARAMETERS
                                                    if name not in COMMAND_LINE_ONLY)))


def display_settings_from_properties(properties):
    """A validated DisplaySettings (overlays, debug passes) from a scene's properties."""
    return DisplaySettings(**_values(properties, DISPLAY_PARAMETERS))


def comparison_settings_from_properties(properties):
    """A validated ComparisonSettings (methods, Cycles samples) from a scene's properties."""
    return ComparisonSettings(**_values(properties, COMPARISON_PARAMETERS))


def register():
    bpy.utils.register_class(LPVPreviewSettings)
    bpy.types.Scene.lpv_preview = bpy.props.PointerProperty(type=LPVPreviewSettings)


def unregister():
    del bpy.types.Scene.lpv_preview
    bpy.utils.unregister_class(LPVPreviewSettings)
