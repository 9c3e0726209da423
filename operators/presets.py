"""The preset buttons: set the pipeline's settings to a named quality level of
gpu/settings.py PRESETS (fast, balanced, accurate)."""
import bpy

from ..gpu.settings import PRESETS


class LPV_OT_apply_preset(bpy.types.Operator):
    bl_idname = "lpv_preview.apply_preset"
    bl_label = "Apply Preset"
    bl_description = "Set the method, map, VPL and volume settings to a quality level chosen from the benchmarks"
    bl_options = {"REGISTER", "UNDO"}

    preset: bpy.props.EnumProperty(
        name="Preset", items=[(name, name.capitalize(), f"The {name} preset of LPV Preview") for name in PRESETS])

    def execute(self, context):
        properties = context.scene.lpv_preview
        for key, value in PRESETS[self.preset].items():
            setattr(properties, key, value)
        self.report({"INFO"}, f"LPV Preview: {self.preset} preset applied.")
        return {"FINISHED"}


register, unregister = bpy.utils.register_classes_factory((LPV_OT_apply_preset,))
