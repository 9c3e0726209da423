"""The name the Cycles sample workers open a .blend with (corrections/sample_workers.py).

A worker unpickles this name as its task arrives, on another thread than the one that runs
the task; Blender must be imported on the thread that then opens the file, so this module
imports bpy only when the function is called."""


def open_sample_renderer(blend_path):
    """A SampleRenderer (cycles_samples.py) of the .blend at `blend_path`."""
    from .cycles_samples import SampleRenderer
    return SampleRenderer(blend_path)
