"""The statistics of the last frame rendered (F12 or viewport), for the panels, and the
warnings they carry: of the OpenGL renderer that made it (a software rasterizer's frames
take many times a GPU's) and of the images it lacked (rendered magenta)."""

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


def missing_images_warning(stats):
    """The one-sentence warning naming the images the frame lacked (the stats'
    "missing_images", from addon/materials.py), or None: for the command line, the
    panel, stats.json and F12's report."""
    names = stats.get("missing_images")
    if not names:
        return None
    one = len(names) == 1
    return (f"{'Image' if one else 'Images'} {', '.join(repr(name) for name in names)} "
            f"{'is' if one else 'are'} missing and render{'s' if one else ''} magenta; find "
            f"{'its file' if one else 'their files'} with File > External Data > Find Missing Files.")


def warnings(stats):
    """Every warning of a frame with these statistics, in order."""
    return [warning for warning in (renderer_warning(stats), missing_images_warning(stats)) if warning]
