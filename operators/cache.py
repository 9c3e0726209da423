"""The button that empties the Cycles reference cache (the comparison panel shows its size)."""
import bpy

from ..addon.cycles_reference import ReferenceCache
from ..gpu.errors import LPVError


class LPV_OT_empty_cycles_cache(bpy.types.Operator):
    bl_idname = "lpv_preview.empty_cycles_cache"
    bl_label = "Empty Cycles Cache"
    bl_description = ("Delete the Cycles references kept from earlier comparisons; the next comparison renders "
                      "them again")

    def execute(self, context):
        cache = ReferenceCache()
        held = cache.describe()
        try:
            cache.empty()
        except LPVError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, f"LPV Preview: deleted {held} from '{cache.folder}'.")
        return {"FINISHED"}


register, unregister = bpy.utils.register_classes_factory((LPV_OT_empty_cycles_cache,))
