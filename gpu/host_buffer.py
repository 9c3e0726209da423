"""A storage buffer in the host's memory, mapped for good, that a shader writes and the
host copies out with several threads: the viewport's rows without the driver's
single-threaded read (docs/performance.md, "The readback")."""
import ctypes
import os
import threading
from concurrent.futures import ThreadPoolExecutor

MAP_READ, MAP_PERSISTENT, MAP_COHERENT, CLIENT_STORAGE = 0x1, 0x40, 0x80, 0x200
CLIENT_MAPPED_BUFFER_BARRIER = 0x4000
COPY_THREADS = min(4, os.cpu_count() or 1)
"""Threads that copy the rows out: one core does not reach the memory's bandwidth, four
do (docs/performance.md, "The readback")."""
COPY_ALIGNMENT = 64

_copy_pool = None
_copy_pool_made = threading.Lock()


def _functions(gl):
    """The GL 4.5 entry points moderngl does not wrap, from its context's loader; None
    where the loader or an entry point is missing."""
    try:
        load = gl.mglo._context.load
    except AttributeError:
        return None
    uint, size = ctypes.c_uint, ctypes.c_ssize_t
    prototypes = {
        "glCreateBuffers": ctypes.CFUNCTYPE(None, ctypes.c_int, ctypes.POINTER(uint)),
        "glNamedBufferStorage": ctypes.CFUNCTYPE(None, uint, size, ctypes.c_void_p, uint),
        "glMapNamedBufferRange": ctypes.CFUNCTYPE(ctypes.c_void_p, uint, size, size, uint),
        "glUnmapNamedBuffer": ctypes.CFUNCTYPE(ctypes.c_ubyte, uint),
        "glDeleteBuffers": ctypes.CFUNCTYPE(None, ctypes.c_int, ctypes.POINTER(uint)),
    }
    functions = {}
    for name, prototype in prototypes.items():
        address = load(name)
        if not address:
            return None
        functions[name] = prototype(address)
    return functions


class HostBuffer:
    """`size` bytes in the host's memory that shaders write through `buffer` (a moderngl
    Buffer to bind) and `read_into` copies out."""

    def __init__(self, gl, size, functions):
        self.gl, self.size, self._functions = gl, size, functions
        name = ctypes.c_uint()
        functions["glCreateBuffers"](1, ctypes.byref(name))
        functions["glNamedBufferStorage"](name, size, None, MAP_READ | MAP_PERSISTENT | MAP_COHERENT | CLIENT_STORAGE)
        self._name = name
        self._address = functions["glMapNamedBufferRange"](name, 0, size, MAP_READ | MAP_PERSISTENT | MAP_COHERENT)
        self.buffer = gl.external_buffer(name.value, size)

    @classmethod
    def make(cls, gl, size):
        """A HostBuffer, or None where the driver cannot map one (the caller then reads
        an ordinary buffer)."""
        functions = _functions(gl)
        if functions is None:
            return None
        gl.clear_errors()
        host = cls(gl, size, functions)
        if not host._address or gl.error != "GL_NO_ERROR":
            host.release()
            return None
        return host

    def bind_to_storage_buffer(self, binding):
        self.buffer.bind_to_storage_buffer(binding)

    def read_into(self, out):
        """Wait for the GPU to finish, then copy the buffer into `out` (a writable buffer
        of at least `size` bytes) in COPY_THREADS parts."""
        global _copy_pool
        self.gl.memory_barrier(CLIENT_MAPPED_BUFFER_BARRIER)
        self.gl.finish()
        view = (ctypes.c_char * self.size).from_buffer(out)  # holds `out`'s buffer while the threads copy
        target = ctypes.addressof(view)
        part = -(-self.size // COPY_THREADS // COPY_ALIGNMENT) * COPY_ALIGNMENT
        starts = range(0, self.size, part)
        if len(starts) == 1:
            ctypes.memmove(target, self._address, self.size)
            return
        with _copy_pool_made:  # GL threads of several contexts may read at once
            if _copy_pool is None:
                _copy_pool = ThreadPoolExecutor(COPY_THREADS, thread_name_prefix="lpv-readback")
        # ctypes lets go of the GIL in memmove, so the parts copy at once.
        list(_copy_pool.map(lambda start: ctypes.memmove(target + start, self._address + start,
                                                         min(part, self.size - start)), starts))

    def release(self):
        if self._name is None:  # released already: GL may have given the name to another buffer
            return
        if self._address:
            self._functions["glUnmapNamedBuffer"](self._name)
            self._address = None
        self._functions["glDeleteBuffers"](1, ctypes.byref(self._name))
        self._name = self.buffer = None
