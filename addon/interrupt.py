"""Ctrl-C while Blender renders.

Blender runs a render engine's Python (Cycles', ours) inside its render operator and
prints, then drops, any exception raised there: a KeyboardInterrupt raised in the middle
of a render would be lost and the render would go on. `interrupt_after_render` records
Ctrl-C instead and raises it once the render call has returned, so that the caller's
clean-up (temporary scene, files, GPU resources) runs and the command stops.
"""
import signal
import threading
from contextlib import contextmanager


@contextmanager
def interrupt_after_render():
    """Hold back Ctrl-C during the body and raise KeyboardInterrupt after it when it came.

    Only where Python's own Ctrl-C handler is installed (the command line, the tests) and
    in the main thread (the only one that may set a signal handler): Blender started with
    -b handles Ctrl-C itself and stops its render, and its window has Esc.
    """
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield
        return
    pressed = []
    signal.signal(signal.SIGINT, lambda signum, frame: pressed.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)
        if pressed:
            raise KeyboardInterrupt
