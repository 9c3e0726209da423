"""A scene's colour management as gpu/colour_management.py ViewTransform: what F12 puts a
render through when it saves a PNG, for the PNGs the command line writes."""
import os

import bpy

from ..gpu.colour_management import ViewTransform

CONFIG = "colormanagement/config.ocio"
"""Where Blender's OCIO config lies in a datafiles folder."""


def blender_ocio_config():
    """The OCIO config Blender reads: $OCIO when it names a file, else config.ocio in the
    user's datafiles, else Blender's own (bpy/5.0/datafiles/colormanagement/config.ocio in
    the bpy module); None when there is none."""
    candidates = [os.environ.get("OCIO", ""), bpy.utils.user_resource("DATAFILES", path=CONFIG),
                  bpy.utils.system_resource("DATAFILES", path=CONFIG),
                  os.path.join(bpy.utils.resource_path("LOCAL"), "datafiles", CONFIG)]
    return next((path for path in candidates if path and os.path.isfile(path)), None)


def scene_view_transform(scene):
    """The view transform F12 saves `scene`'s render with: the output's own colour
    management when its image settings override the scene's (Output properties, Color
    Management: Override), else the scene's (Render properties, Color Management): view,
    look, exposure, gamma and display, in Blender's OCIO config."""
    image = scene.render.image_settings
    owner = image if image.color_management == "OVERRIDE" else scene
    view = owner.view_settings
    return ViewTransform(config=blender_ocio_config(), display=owner.display_settings.display_device,
                         view=view.view_transform, look=view.look, exposure=view.exposure, gamma=view.gamma)
