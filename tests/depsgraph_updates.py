"""The updates Blender's depsgraph reports for an edit, recorded as the engine's view_update records them."""
import bpy

from lpv_preview.addon.sync import record_updates


def recorded_updates(edit):
    """The RecordedUpdates of what `edit()` changes, after the view layer settled."""
    records = []

    def handler(scene, depsgraph):
        records.extend(record_updates(depsgraph))

    bpy.context.view_layer.update()
    bpy.app.handlers.depsgraph_update_post.append(handler)
    try:
        edit()
        bpy.context.view_layer.update()
    finally:
        bpy.app.handlers.depsgraph_update_post.remove(handler)
    return records
