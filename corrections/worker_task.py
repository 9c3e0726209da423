"""The task a Cycles sample worker runs (corrections/sample_workers.py): the .blend opened
once a process by the renderer the master names (addon/cycles_samples.py SampleRenderer,
passed by reference, so that this module needs neither bpy nor addon/: a Dask worker
unpickles it before anything else), and requests rendered with it."""
import atexit
import os

_RENDERERS = {}  # in a worker process: (.blend path, its modification time and size) -> renderer


def close_renderers():
    """In a worker: remove the renderer's folder as the process ends (a studio's long-lived
    worker; a local cluster removes its workers' whole folder anyway)."""
    for opened in _RENDERERS.values():
        opened.close()
    _RENDERERS.clear()


atexit.register(close_renderers)


def renderer(open_renderer, blend_path):
    """In a worker: its renderer of the .blend at `blend_path`, opened once a process by
    `open_renderer(blend_path)`."""
    try:
        saved = os.stat(blend_path)
        key = (blend_path, saved.st_mtime_ns, saved.st_size)  # a file saved again is opened again
    except OSError:
        key = (blend_path,)  # SampleRenderer says there is none
    if key not in _RENDERERS:
        close_renderers()
        _RENDERERS[key] = open_renderer(blend_path)
    return _RENDERERS[key]


def open_blend(open_renderer, blend_path):
    """In a worker: open the .blend now (before requests come)."""
    renderer(open_renderer, blend_path)


def render_request(open_renderer, blend_path, request, threads=None):
    """In a worker: the SampleResult of `request` on the .blend at `blend_path`, Cycles on
    `threads` threads (None: all the machine's)."""
    return renderer(open_renderer, blend_path).render(request, threads)
