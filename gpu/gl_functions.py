"""The GL entry points moderngl does not wrap (buffer storage and mapping, fences, flush),
loaded once per context from moderngl's own loader."""
import ctypes

_uint, _size = ctypes.c_uint, ctypes.c_ssize_t
PROTOTYPES = {
    "glCreateBuffers": ctypes.CFUNCTYPE(None, ctypes.c_int, ctypes.POINTER(_uint)),
    "glNamedBufferStorage": ctypes.CFUNCTYPE(None, _uint, _size, ctypes.c_void_p, _uint),
    "glMapNamedBufferRange": ctypes.CFUNCTYPE(ctypes.c_void_p, _uint, _size, _size, _uint),
    "glUnmapNamedBuffer": ctypes.CFUNCTYPE(ctypes.c_ubyte, _uint),
    "glDeleteBuffers": ctypes.CFUNCTYPE(None, ctypes.c_int, ctypes.POINTER(_uint)),
    "glFenceSync": ctypes.CFUNCTYPE(ctypes.c_void_p, _uint, _uint),
    "glClientWaitSync": ctypes.CFUNCTYPE(_uint, ctypes.c_void_p, _uint, ctypes.c_uint64),
    "glDeleteSync": ctypes.CFUNCTYPE(None, ctypes.c_void_p),
    "glFlush": ctypes.CFUNCTYPE(None),
}


def gl_functions(gl):
    """{name: function} of the PROTOTYPES the loader of `gl` (a moderngl Context) gives,
    made once and kept on the context; those it lacks are left out (WGL's loader gives no
    GL 1.1 function), and all where it has no loader."""
    functions = getattr(gl, "lpv_functions", None)
    if functions is None:
        try:
            load = gl.mglo._context.load
        except AttributeError:
            load = lambda name: 0  # noqa: E731 (a context without a loader gives nothing)
        addresses = {name: load(name) for name in PROTOTYPES}
        functions = gl.lpv_functions = {name: PROTOTYPES[name](address) for name, address in addresses.items() if address}
    return functions
