"""Buffers in the host's memory, mapped for good, that the host copies with several
threads: the viewport's rows out (a shader writes them) without the driver's
single-threaded read, and the emitters' rows in (the GPU copies them on at the bus's
speed) without the driver's single-threaded write (docs/performance.md, "The readback",
"An emitter frame")."""
import ctypes
import os
import threading
from concurrent.futures import ThreadPoolExecutor

from .gl_functions import gl_functions

MAP_READ, MAP_WRITE, MAP_PERSISTENT, MAP_COHERENT, CLIENT_STORAGE = 0x1, 0x2, 0x40, 0x80, 0x200
SYNC_GPU_COMMANDS_COMPLETE, SYNC_FLUSH_COMMANDS = 0x9117, 0x1
WAIT_FOREVER_NS = 0xFFFFFFFFFFFFFFFF
CLIENT_MAPPED_BUFFER_BARRIER = 0x4000
COPY_THREADS = min(8, os.cpu_count() or 1)
"""Threads that copy rows out and in: one core does not reach the memory's bandwidth
(docs/performance.md, "The readback", "An emitter frame")."""
COPY_ALIGNMENT = 64

_copy_pool = None
_copy_pool_made = threading.Lock()


MAPPING_FUNCTIONS = ("glCreateBuffers", "glNamedBufferStorage", "glMapNamedBufferRange", "glUnmapNamedBuffer",
                     "glDeleteBuffers", "glFenceSync", "glClientWaitSync", "glDeleteSync")
"""The entry points a MappedBuffer needs (gpu/gl_functions.py)."""


class MappedBuffer:
    """`size` bytes in the host's memory, mapped for good at `_address`, that the GPU reaches
    through `buffer` (a moderngl Buffer); ACCESS says whether the host reads or writes it."""

    ACCESS = 0

    def __init__(self, gl, size, functions):
        self.gl, self.size, self._functions = gl, size, functions
        name = ctypes.c_uint()
        functions["glCreateBuffers"](1, ctypes.byref(name))
        functions["glNamedBufferStorage"](name, size, None, self.ACCESS | MAP_PERSISTENT | MAP_COHERENT | CLIENT_STORAGE)
        self._name = name
        self._address = functions["glMapNamedBufferRange"](name, 0, size, self.ACCESS | MAP_PERSISTENT | MAP_COHERENT)
        self.buffer = gl.external_buffer(name.value, size)

    @classmethod
    def make(cls, gl, size):
        """One of `size` bytes, or None where the driver cannot map one (the caller then
        has the driver read or write an ordinary buffer)."""
        functions = gl_functions(gl)
        if not all(name in functions for name in MAPPING_FUNCTIONS):
            return None
        gl.clear_errors()
        host = cls(gl, size, functions)
        if not host._address or gl.error != "GL_NO_ERROR":
            host.release()
            return None
        return host

    def release(self):
        if self._name is None:  # released already: GL may have given the name to another buffer
            return
        if self._address:
            self._functions["glUnmapNamedBuffer"](self._name)
            self._address = None
        self._functions["glDeleteBuffers"](1, ctypes.byref(self._name))
        self._name = self.buffer = None


class HostBuffer(MappedBuffer):
    """A MappedBuffer that shaders write and `read_into` copies out."""

    ACCESS = MAP_READ

    def bind_to_storage_buffer(self, binding):
        self.buffer.bind_to_storage_buffer(binding)

    def read_into(self, out):
        """Wait for the GPU to finish, then copy the buffer into `out` (a writable buffer
        of at least `size` bytes) in COPY_THREADS parts."""
        self.gl.memory_barrier(CLIENT_MAPPED_BUFFER_BARRIER)
        self.gl.finish()
        view = (ctypes.c_char * self.size).from_buffer(out)  # holds `out`'s buffer while the threads copy
        _copy_in_parts(ctypes.addressof(view), self._address, self.size)


class UploadBuffer(MappedBuffer):
    """A MappedBuffer that `write` fills with several threads and the GPU copies into an
    ordinary buffer."""

    ACCESS = MAP_WRITE

    def __init__(self, gl, size, functions):
        super().__init__(gl, size, functions)
        self._copied = None  # the fence of the GPU's last copy out of this buffer

    def write(self, target, arrays, offset=0):
        """Copy `arrays` (contiguous numpy arrays) one after another into `target` (a
        moderngl Buffer) from byte `offset` on, a buffer's size at a time: the host waits
        only where it would fill the buffer before the GPU copied out what it held."""
        filled = 0
        for array in arrays:
            source, left = array.ctypes.data, array.nbytes
            while left:
                if not filled:
                    self._wait()
                part = min(left, self.size - filled)
                _copy_in_parts(self._address + filled, source, part)
                filled, source, left = filled + part, source + part, left - part
                if filled == self.size:
                    offset = self._send(target, filled, offset)
                    filled = 0
        if filled:
            self._send(target, filled, offset)

    def _wait(self):
        if self._copied is not None:
            self._functions["glClientWaitSync"](self._copied, SYNC_FLUSH_COMMANDS, WAIT_FOREVER_NS)
            self._functions["glDeleteSync"](self._copied)
            self._copied = None

    def _send(self, target, size, offset):
        """Have the GPU copy the first `size` bytes to `offset` in `target`; the offset after."""
        self.gl.copy_buffer(target, self.buffer, size=size, write_offset=offset)
        self._copied = self._functions["glFenceSync"](SYNC_GPU_COMMANDS_COMPLETE, 0)
        return offset + size

    def release(self):
        if self._copied is not None:
            self._functions["glDeleteSync"](self._copied)
            self._copied = None
        super().release()


def _copy_in_parts(target, source, size):
    """Copy `size` bytes from address `source` to `target` in COPY_THREADS parts at once."""
    global _copy_pool
    part = -(-size // COPY_THREADS // COPY_ALIGNMENT) * COPY_ALIGNMENT
    starts = range(0, size, part) if size else ()
    if len(starts) <= 1:
        ctypes.memmove(target, source, size)
        return
    with _copy_pool_made:  # GL threads of several contexts may copy at once
        if _copy_pool is None:
            _copy_pool = ThreadPoolExecutor(COPY_THREADS, thread_name_prefix="lpv-copy")
    # ctypes lets go of the GIL in memmove, so the parts copy at once.
    list(_copy_pool.map(lambda start: ctypes.memmove(target + start, source + start, min(part, size - start)), starts))
