"""The OpenImageIO module, found where Blender keeps it: this Python's, else the copy
Blender ships among its own Python's packages (Blender as a module leaves that folder off
sys.path)."""
import importlib.machinery
import importlib.util
import os
import sys

from .errors import LPVError

NO_OPENIMAGEIO = ("Reading and writing images needs the OpenImageIO module, which neither this Python nor Blender's "
                  "bundled packages hold; use Blender 5.0 from blender.org, which ships it, or install "
                  "requirements.txt (bash scripts/setup.sh).")


def openimageio():
    """The OpenImageIO module: this Python's, else the copy Blender ships among its own
    Python's packages (Blender as a module leaves that folder off sys.path); refused in one
    sentence where neither is, so callers can check before any work."""
    try:
        import OpenImageIO
        return OpenImageIO
    except ImportError:
        pass
    for folder in blender_package_folders():
        spec = importlib.machinery.PathFinder.find_spec("OpenImageIO", [folder])
        if spec is not None:
            module = importlib.util.module_from_spec(spec)
            sys.modules["OpenImageIO"] = module
            try:
                spec.loader.exec_module(module)
            except ImportError:
                del sys.modules["OpenImageIO"]
                continue
            return module
    raise LPVError(NO_OPENIMAGEIO)


def blender_package_folders():
    """The folders of Blender's bundled Python packages (Linux and macOS, then Windows),
    when bpy is loaded; gpu/ does not import bpy itself."""
    bpy = sys.modules.get("bpy")
    utils = getattr(bpy, "utils", None)
    if utils is None:
        return []
    python = os.path.join(utils.resource_path("LOCAL"), "python", "lib")
    return [os.path.join(python, f"python{sys.version_info[0]}.{sys.version_info[1]}", "site-packages"),
            os.path.join(python, "site-packages")]
