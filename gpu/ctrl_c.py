"""Ctrl-C held back through work it must not cut in two: a shader's compile (moderngl
stores what its Python helpers return unchecked, so a KeyboardInterrupt raised in one
crashes the process), the making or removal of a temporary folder (cut in two, it would
stay behind) and a Blender render (Blender runs a render engine's Python, Cycles' or
ours, inside its render operator and prints, then drops, an exception raised there: a
KeyboardInterrupt in the middle of a render would be lost and the render would go on;
raised once the render call has returned, the caller's clean-up runs and the command
stops). Blender started with -b handles Ctrl-C itself, and its window has Esc."""
import signal
import threading
from contextlib import contextmanager


@contextmanager
def ctrl_c_held():
    """Hold Ctrl-C's Python handler back through the body and call it after, where Ctrl-C
    came. Handlers run in the main thread only, so only there is one held back."""
    handler = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or not callable(handler):
        yield
        return
    pressed = []  # not the frame: it would keep the body's objects (a render's engine) alive
    signal.signal(signal.SIGINT, lambda signum, frame: pressed.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, handler)
        if pressed:
            handler(pressed[0], None)
