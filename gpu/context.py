"""Our OpenGL 4.5 context, the shaders it runs, and wall-clock timing.

The context is made through the platform's own interface: EGL on Linux (headless, beside
Wayland, and beside X11 on a thread of its own; GLX where EGL cannot make one and a
display is there), WGL on Windows. The environment variable LPV_PREVIEW_GL_BACKEND
(`egl`, `glx`, `wgl`) picks one instead. macOS has none: Apple's OpenGL stops at 4.1.
The GPU driver is used when there is one, Mesa's llvmpipe otherwise. Setting
LPV_PREVIEW_NO_GPU=1 makes context creation fail as it would on a machine without any
OpenGL 4.5 driver, so that path can be tested.

A context is current on the thread that made it and used there only: each thread that
renders has its own (`GLContext.shared()`). Inside Blender that is one thread of ours
(gpu/gl_thread.py), never Blender's drawing thread, whose own context stays current.
"""
import os
import sys
import threading
import time
from contextlib import contextmanager
from pathlib import Path

from .ctrl_c import ctrl_c_held
from .errors import LPVError
from .gl_functions import gl_functions
from .host_buffer import UploadBuffer
from .specular_albedo import texture_rows

SHADER_DIR = Path(__file__).parent / "shaders"
NO_GPU_VARIABLE = "LPV_PREVIEW_NO_GPU"
BACKEND_VARIABLE = "LPV_PREVIEW_GL_BACKEND"
BACKENDS = {"egl": "egl", "glx": None, "wgl": None}
"""Our names for the context interfaces and moderngl's backend argument for each (None:
glcontext's default for the platform, GLX on Linux and WGL on Windows)."""


def platform_backends(platform=None, environment=None):
    """The interfaces to try, in order, on `platform` (sys.platform) with `environment`
    (os.environ): the one LPV_PREVIEW_GL_BACKEND names, else the platform's."""
    platform = sys.platform if platform is None else platform
    environment = os.environ if environment is None else environment
    chosen = environment.get(BACKEND_VARIABLE, "").strip().lower()
    if chosen:
        if chosen not in BACKENDS:
            raise LPVError(f"{BACKEND_VARIABLE}={chosen} names no OpenGL interface; set it to one of "
                           f"{', '.join(BACKENDS)}, or unset it.")
        return (chosen,)
    if platform.startswith("win"):
        return ("wgl",)
    if platform == "darwin":
        raise LPVError("LPV Preview needs OpenGL 4.5 with compute shaders, which macOS lacks (Apple's OpenGL stops "
                       "at 4.1); render on Linux or Windows.")
    return ("egl", "glx") if environment.get("DISPLAY") else ("egl",)


def install_hint(platform=None):
    """What to do when no OpenGL 4.5 context can be made on `platform`."""
    platform = sys.platform if platform is None else platform
    if platform.startswith("win"):
        return ("install your GPU vendor's current driver, with OpenGL 4.5 (Windows' own display driver has "
                "none)")
    return ("install an OpenGL 4.5 driver with EGL: your GPU vendor's, or Mesa's (Debian/Ubuntu: apt-get install "
            f"libegl1 libgl1-mesa-dri); beside X11, {BACKEND_VARIABLE}=glx uses GLX instead")


class GLContext:
    """One standalone moderngl context, current on the thread that made it, and a cache
    of the programs compiled in it.

    `GLContext.shared()` is the calling thread's one context: moderngl objects do not
    make their own context current, so everything a thread renders lives in its one
    context. An EEVEE render on the same thread makes Blender's GPU context current and
    leaves it so: it goes inside `foreign_render()`.
    """

    _threads = threading.local()
    last_made = None
    """The context this process made last, on any thread: what names the renderer a
    command's frames used."""

    @classmethod
    def shared(cls):
        if os.environ.get(NO_GPU_VARIABLE):
            cls()  # raises the same error a machine without OpenGL 4.5 gives
        if getattr(cls._threads, "context", None) is None:
            cls._threads.context = cls()
        return cls._threads.context

    def __init__(self):
        if os.environ.get(NO_GPU_VARIABLE):
            raise LPVError(f"No OpenGL 4.5 context is available ({NO_GPU_VARIABLE} is set); "
                           f"unset it, or {install_hint()}.")
        try:
            import moderngl
        except ImportError as error:
            raise LPVError(f"The Python package moderngl is missing ({error}); run the README's set-up command.")
        failures = []
        for backend in platform_backends():
            try:
                options = {"backend": BACKENDS[backend]} if BACKENDS[backend] else {}
                self.gl = moderngl.create_standalone_context(require=450, **options)
                break
            except Exception as error:  # moderngl raises plain Exception for a missing library or GL 4.5
                failures.append(f"{backend.upper()}: {str(error).strip().splitlines()[0] if str(error) else error}")
        else:
            raise LPVError(f"No OpenGL 4.5 context could be made ({'; '.join(failures)}); {install_hint()}.")
        self.backend = backend
        GLContext.last_made = self
        self.renderer = self.gl.info["GL_RENDERER"]
        self.version = self.gl.info["GL_VERSION"]
        self.is_software = any(name in self.renderer.lower() for name in ("llvmpipe", "softpipe", "swrast"))
        self._programs = {}
        self._timed_queries = []  # (stats, key, query) of timed blocks not read yet
        self._idle_queries = []
        self._free = {}  # (kind, size, ...) -> released textures, depth renderbuffers, buffers to reuse
        self._specular_albedo = None  # the glossy layer's table, made on first use
        self._upload = None  # the UploadBuffer of `write`, made on first use and grown (False: none maps)

    @classmethod
    @contextmanager
    def foreign_render(cls):
        """A block in which Blender renders with its GPU (EEVEE), which leaves its own
        context current: this thread's, once made, is current again after it."""
        try:
            yield
        finally:
            context = getattr(cls._threads, "context", None)
            if context is not None:
                context.gl.__enter__()

    def use_specular_albedo(self, program, unit):
        """Bind the glossy layer's table (gpu/specular_albedo.py) to texture `unit` for
        `program`'s `specular_albedo_table`; made on first use."""
        if self._specular_albedo is None:
            rows = texture_rows()
            texture = self.gl.texture((rows.shape[1], rows.shape[0]), 3, rows.tobytes(), dtype="f4")
            texture.repeat_x = texture.repeat_y = False
            self._specular_albedo = texture
        self._specular_albedo.use(location=unit)
        set_uniforms(program, specular_albedo_table=unit)

    def texture(self, size, components, dtype="f4"):
        """A 2D texture with nearest filtering, reused from `recycle` when one of the same
        shape is free: allocation must not land in a stage's timing or churn memory."""
        free = self._free.get(("texture", tuple(size), components, dtype))
        if free:
            return free.pop()
        texture = self.gl.texture(tuple(size), components, dtype=dtype)
        texture.filter = (self.gl.NEAREST, self.gl.NEAREST)
        return texture

    def depth_renderbuffer(self, size):
        free = self._free.get(("depth", tuple(size), 1, "f4"))
        return free.pop() if free else self.gl.depth_renderbuffer(tuple(size))

    def write(self, buffer, arrays, offset=0):
        """Write `arrays` (contiguous numpy arrays) one after another into `buffer` from byte
        `offset` on: together at least STAGED_WRITE_BYTES through an UploadBuffer
        (gpu/host_buffer.py) of at most UPLOAD_BYTES_MOST, whose copy several threads
        make, where the driver's write copies on one; smaller ones, or where no buffer
        maps, by the driver."""
        total = sum(array.nbytes for array in arrays)
        if total >= STAGED_WRITE_BYTES and self._upload is not False:
            size = min(1 << (total - 1).bit_length(), UPLOAD_BYTES_MOST)
            if self._upload is None or self._upload.size < size:
                if self._upload is not None:
                    self._upload.release()
                self._upload = UploadBuffer.make(self.gl, size) or False
            if self._upload:
                self._upload.write(buffer, arrays, offset)
                return
        for array in arrays:
            buffer.write(array, offset=offset)
            offset += array.nbytes

    def scratch_buffer(self, size):
        """A buffer of `size` bytes, a free one where `recycle` was given one."""
        free = self._free.get(("buffer", size))
        return free.pop() if free else self.gl.buffer(reserve=size)

    def recycle(self, *resources):
        """Give textures, depth renderbuffers and buffers from `texture`,
        `depth_renderbuffer` and `scratch_buffer` back."""
        for resource in resources:
            if hasattr(resource, "filter"):  # a texture; depth renderbuffers have no filtering
                key = ("texture", tuple(resource.size), resource.components, resource.dtype)
            elif hasattr(resource, "orphan"):  # a buffer
                key = ("buffer", resource.size)
            else:
                key = ("depth", tuple(resource.size), 1, "f4")
            self._free.setdefault(key, []).append(resource)

    def clear(self, *textures):
        """Zero float colour textures: by a compute pass on a GPU (shaders/zero_image.comp),
        through a framebuffer on llvmpipe, whose clear is a memset and whose compute pass
        is five times slower."""
        for texture in textures:
            if self.is_software:
                framebuffer = self.gl.framebuffer(color_attachments=[texture])
                framebuffer.clear(0.0, 0.0, 0.0, 0.0)
                framebuffer.release()
                continue
            program = self.compute("zero_image", FORMAT=IMAGE_FORMATS[texture.dtype, texture.components])
            texture.bind_to_image(0, read=False, write=True)
            dispatch(program, *texture.size)

    def compute(self, name, **defines):
        """The compute shader `shaders/<name>.comp`, compiled once per set of defines."""
        key = (name, tuple(sorted(defines.items())))
        if key not in self._programs:
            with ctrl_c_held():
                self._programs[key] = self.gl.compute_shader(load_shader(f"{name}.comp", defines))
        return self._programs[key]

    def program(self, vertex, fragment, geometry=None, tessellation=None, **defines):
        """The program of `shaders/<vertex>.vert`, `<fragment>.frag`, optionally
        `<geometry>.geom` and `<tessellation>.tesc/.tese`, compiled once."""
        if self.is_software:  # shaders/surface.glsl filters images texel by texel there
            defines = {**defines, "TEXEL_FILTER": 1}
        key = (vertex, fragment, geometry, tessellation, tuple(sorted(defines.items())))
        if key not in self._programs:
            stages = {"vertex_shader": load_shader(f"{vertex}.vert", defines),
                      "fragment_shader": load_shader(f"{fragment}.frag", defines)}
            if geometry is not None:
                stages["geometry_shader"] = load_shader(f"{geometry}.geom", defines)
            if tessellation is not None:
                stages["tess_control_shader"] = load_shader(f"{tessellation}.tesc", defines)
                stages["tess_evaluation_shader"] = load_shader(f"{tessellation}.tese", defines)
            with ctrl_c_held():
                self._programs[key] = self.gl.program(**stages)
        return self._programs[key]

    @contextmanager
    def timed(self, stats, stage):
        """Add the block's milliseconds to stats[stage]. On llvmpipe, whose timer queries
        do not work, the GPU finishes before and after: they are the stage's wall clock.
        Elsewhere nothing waits (a finish between stages left the GPU idle while Python
        made the next one): stats[stage] is the host's time in the block, and a timer
        query's GPU milliseconds go to stats["gpu_" + stage] at `read_timings`. Blocks
        must not nest (GL timer queries cannot)."""
        if self.is_software:
            self.gl.finish()
            start = time.perf_counter()
            yield
            self.gl.finish()
        else:
            query = self._idle_queries.pop() if self._idle_queries else self.gl.query(time=True)
            start = time.perf_counter()
            with query:
                yield
            self._timed_queries.append((stats, "gpu_" + stage, query))
        stats[stage] = stats.get(stage, 0.0) + (time.perf_counter() - start) * 1000.0

    def read_timings(self):
        """Add the GPU milliseconds of the blocks timed since the last call to their stats
        (waiting for the GPU to finish them)."""
        for stats, key, query in self._timed_queries:
            stats[key] = stats.get(key, 0.0) + query.elapsed / 1e6
            self._idle_queries.append(query)
        self._timed_queries.clear()

    def release(self):
        for program in self._programs.values():
            program.release()
        self._programs.clear()
        for resources in self._free.values():
            for resource in resources:
                resource.release()
        self._free.clear()
        if self._upload:
            self._upload.release()
        self.gl.release()


STAGED_WRITE_BYTES, UPLOAD_BYTES_MOST = 1 << 20, 1 << 26
"""Writes from the first size on go through the context's UploadBuffer (`GLContext.write`),
which holds at most the second (pinned host memory) and copies larger ones in parts."""

DTYPE_BYTES = {"f1": 1, "f2": 2, "f4": 4, "u1": 1, "u2": 2, "u4": 4, "i1": 1, "i2": 2, "i4": 4}


def resource_bytes(*resources):
    """GPU memory of moderngl buffers and textures (2D, 3D and arrays, an array's mip
    chain counted as the third more it takes), as allocated."""
    import moderngl
    total = 0
    for resource in resources:
        if isinstance(resource, moderngl.Buffer):
            total += resource.size
            continue
        # A 2D texture's `depth` says whether it is a depth texture; a 3D one's is its depth.
        layers = resource.depth if isinstance(resource, moderngl.Texture3D) else 1
        texels = resource.width * resource.height * layers
        if isinstance(resource, moderngl.TextureArray):
            texels = resource.width * resource.height * resource.layers * 4 // 3
        total += texels * resource.components * DTYPE_BYTES[resource.dtype]
    return total


def load_shader(filename, defines=None):
    """GLSL source of shaders/<filename>, preprocessed."""
    return preprocess((SHADER_DIR / filename).read_text(), defines)


def preprocess(source, defines=None):
    """Expand `#include "x.glsl"` (from shaders/, recursively, each file once) and insert
    `#define`s after `#version`."""
    text = _expand_includes(source, set())
    if defines:
        head, _, rest = text.partition("\n")
        text = head + "\n" + "".join(f"#define {k} {v}\n" for k, v in defines.items()) + rest
    return text


def _expand_includes(source, included):
    lines = []
    for line in source.splitlines():
        if line.startswith("#include"):
            name = line.split('"')[1]
            if name not in included:
                included.add(name)
                lines.append(_expand_includes((SHADER_DIR / name).read_text(), included))
        else:
            lines.append(line)
    return "\n".join(lines)


def set_uniforms(program, **values):
    """Set uniforms by name; a uniform the driver optimised away is skipped.

    Matrices are numpy 4x4 arrays in row-major (mathematical) order; arrays of them are
    (k, 4, 4). They are transposed into GL's column-major layout here.
    """
    import numpy as np
    for name, value in values.items():
        member = program.get(name, None)
        if member is None:
            continue
        if isinstance(value, np.ndarray) and value.shape[-2:] == (4, 4):
            member.write(np.ascontiguousarray(np.swapaxes(value, -1, -2), dtype=np.float32).tobytes())
        elif isinstance(value, np.ndarray):
            member.write(np.ascontiguousarray(value, dtype=np.int32 if value.dtype.kind == "i" else np.float32).tobytes())
        else:
            member.value = value


GUARANTEED_WORKGROUPS = 65535
"""Workgroups GL promises a dispatch along each axis (GL_MAX_COMPUTE_WORK_GROUP_COUNT's least)."""
ROW_INVOCATIONS = 64 * GUARANTEED_WORKGROUPS
"""Invocations one dispatch of a row of 64-wide workgroups reaches."""


def dispatch_row(program, count, first, **uniforms):
    """Run a shader of 64-wide workgroups over `count` invocations, ROW_INVOCATIONS a
    dispatch, the uniform named `first` telling each dispatch where it starts."""
    for start in range(0, count, ROW_INVOCATIONS):
        set_uniforms(program, **uniforms, **{first: start})
        dispatch(program, min(ROW_INVOCATIONS, count - start), local=(64,))


WORKGROUP_ROW = 32768
"""Workgroups along x in `run_workgroups`: GL guarantees 65,535."""


def run_workgroups(program, count):
    """Run `count` workgroups of a shader that numbers them gl_WorkGroupID.y * rows +
    gl_WorkGroupID.x (rows of WORKGROUP_ROW), its writes made visible."""
    program.run(min(count, WORKGROUP_ROW), -(-count // WORKGROUP_ROW), 1)
    program.ctx.memory_barrier()
    submit(program.ctx)


IMAGE_FORMATS = {("f4", 4): "rgba32f", ("f2", 4): "rgba16f", ("f4", 1): "r32f", ("f2", 1): "r16f"}
"""The GLSL image format of a float texture's (dtype, components)."""


def made_or_refused(gl, make, what, remedy):
    """The textures `make()` returns (a tuple), or, where the driver refused them within its
    size limits (GL_OUT_OF_MEMORY, which moderngl does not raise: llvmpipe makes no texture
    over 1 GiB), an LPVError in one sentence naming `what` and the `remedy`."""
    while gl.error != "GL_NO_ERROR":
        pass  # forget earlier errors: Mesa keeps only the first, which would hide these
    textures = make()
    if gl.error == "GL_OUT_OF_MEMORY":
        for texture in textures:
            texture.release()
        raise LPVError(f"{gl.info['GL_RENDERER']} cannot make {what} (GL_OUT_OF_MEMORY); {remedy}.")
    return textures


def clear_depth_only(framebuffer):
    """Clear a framebuffer's depth and leave its colour as it is."""
    masks = framebuffer.color_mask
    framebuffer.color_mask = tuple((False,) * 4 for _ in masks)
    framebuffer.clear(depth=1.0)
    framebuffer.color_mask = masks


def zero_buffer(glc, buffer):
    """Zero `buffer` on the GPU (shaders/zero_buffer.comp)."""
    buffer.bind_to_storage_buffer(0)
    words = buffer.size // 4
    dispatch_row(glc.compute("zero_buffer"), words, "first_word", word_count=words)


def dispatch(program, *counts, local=(8, 8, 1)):
    """Run a compute shader over `counts` invocations, make its writes visible and hand it
    to the GPU (`submit`)."""
    groups = [max(1, -(-c // l)) for c, l in zip(counts, local)]
    groups += [1] * (3 - len(groups))
    if max(groups) > GUARANTEED_WORKGROUPS:  # past the driver's limit GL runs nothing, and says so only in glGetError
        limits = program.ctx.info["GL_MAX_COMPUTE_WORK_GROUP_COUNT"]
        if any(g > limit for g, limit in zip(groups, limits)):
            raise ValueError(f"{groups} workgroups exceed the driver's {limits}: dispatch them in rows")
    program.run(*groups)
    program.ctx.memory_barrier()
    submit(program.ctx)


def dispatch_indirect(program, command):
    """Run a compute shader as many workgroups as the dispatch command at the head of
    `command` (a buffer the GPU filled) says, make its writes visible and hand it to the GPU."""
    program.run_indirect(command)
    program.ctx.memory_barrier()
    submit(program.ctx)


def submit(gl):
    """Hand the commands issued so far to the GPU (glFlush, which moderngl does not wrap;
    nothing where the loader lacks it): after each wait for a result, the driver held the
    next commands back, the GPU idle (docs/performance.md, "An emitter frame")."""
    flush = gl_functions(gl).get("glFlush")
    if flush is not None:
        flush()
