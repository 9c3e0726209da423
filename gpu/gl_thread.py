"""The one thread that owns our OpenGL context inside Blender.

Blender draws on its own thread with its own GL context current; a context of ours made
current there would fight it (on X11, libglvnd refuses EGL while GLX is current, and the
failure would go unnoticed). So every GL call of the engine runs on this thread, where
our context (gpu/context.py `GLContext.shared()`) is made and stays current; Blender's
thread only hands it work and takes finished frames back. The command line and the tests,
which have no GL context of Blender's, render on their own thread.
"""
import threading
from concurrent.futures import ThreadPoolExecutor


class GLThread:
    """A single worker thread; `call` runs a function there and waits, `submit` returns
    its Future at once."""

    _shared = None
    _lock = threading.Lock()

    def __init__(self):
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="lpv_preview_gl")
        self._thread = None
        self.submit(self._note_thread).result()

    @classmethod
    def shared(cls):
        """The process's one GL thread, started on first use."""
        with cls._lock:
            if cls._shared is None:
                cls._shared = cls()
            return cls._shared

    def _note_thread(self):
        self._thread = threading.current_thread()

    @property
    def is_current(self):
        """Whether the calling code runs on this thread."""
        return threading.current_thread() is self._thread

    def submit(self, function, *args, **kwargs):
        """A Future of `function(*args, **kwargs)` run on this thread."""
        return self._executor.submit(function, *args, **kwargs)

    def call(self, function, *args, **kwargs):
        """`function(*args, **kwargs)` run on this thread (at once when called from it);
        its result, or its exception raised here."""
        if self.is_current:
            return function(*args, **kwargs)
        return self.submit(function, *args, **kwargs).result()
