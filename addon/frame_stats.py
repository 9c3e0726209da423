"""The statistics of the last frame rendered (F12 or viewport), for the panels, and what
they say of the OpenGL renderer that made it (a software rasterizer is worth a warning:
its frames take many times a GPU's)."""

_last = {}


def last_stats():
    return _last


def remember(stats):
    _last.clear()
    _last.update(stats)


def forget():
    _last.clear()


def renderer_warning(stats):
    """The one-sentence warning for frames rendered by a software rasterizer (the stats'
    "software_renderer", from gpu/pipeline.py), or None: for the command line, the panel,
    the EXR header and F12's report."""
    if not stats.get("software_renderer"):
        return None
    return (f"OpenGL renders on the CPU here ({stats.get('renderer', 'a software rasterizer')}), many times slower "
            f"than on a GPU; install the GPU's OpenGL 4.5 driver with EGL to render on it.")
