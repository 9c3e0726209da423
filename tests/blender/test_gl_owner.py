"""Our GL context has one owner, the GL thread (gpu/gl_thread.py): under a real X server
(Xvfb) with a GLX context current on the main thread, as Blender's is while it draws,
viewport frames and F12 render, and that context is still current with its state
untouched; with no display at all the same frames render, and both match."""
import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

pytest.importorskip("bpy")

SIZE = 48
SCRIPT = textwrap.dedent(f"""
    import ctypes, json, sys, time
    import numpy as np
    mode, out = sys.argv[1], sys.argv[2]
    report = {{}}
    if mode == "glx":
        import moderngl
        # Blender's own context: GLX (glcontext's default on Linux), current on this thread
        blender_like = moderngl.create_standalone_context(require=330)
        libgl = ctypes.CDLL("libGL.so.1")
        libgl.glXGetCurrentContext.restype = ctypes.c_void_p

        def gl_state():
            clear, viewport, framebuffer = (ctypes.c_float * 4)(), (ctypes.c_int * 4)(), ctypes.c_int()
            libgl.glGetFloatv(0x0C22, clear)  # GL_COLOR_CLEAR_VALUE
            libgl.glGetIntegerv(0x0BA2, viewport)  # GL_VIEWPORT
            libgl.glGetIntegerv(0x8CA6, ctypes.byref(framebuffer))  # GL_DRAW_FRAMEBUFFER_BINDING
            return {{"context": libgl.glXGetCurrentContext(), "clear": list(clear), "viewport": list(viewport),
                    "framebuffer": framebuffer.value}}
        target = blender_like.framebuffer([blender_like.texture((7, 5), 4)])
        target.use()
        blender_like.clear(0.25, 0.5, 0.75, 1.0)
        report["before"] = gl_state()

    import bpy, lpv_preview
    from lpv_preview import demo
    from lpv_preview.addon.extract import extract_camera
    from lpv_preview.addon.viewport import ViewportSession
    from lpv_preview.gpu.context import GLContext
    from lpv_preview.gpu.image_io import read_exr_channels
    scene = demo.build("cornell")
    lpv_preview.register()
    settings = scene.lpv_preview
    settings.rsm_resolution, settings.vpls_per_light, settings.lpv_resolution = 64, 256, 16
    settings.viewport_vpl_sets = 3
    scene.render.engine = "LPV_PREVIEW"
    scene.render.resolution_x = scene.render.resolution_y = {SIZE}
    scene.render.resolution_percentage = 100
    session = ViewportSession()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    camera = extract_camera(depsgraph, ({SIZE}, {SIZE}))
    report["first_redraw_waits"] = session.redraw(depsgraph, camera, ({SIZE}, {SIZE})) is not None
    sets = []
    for _ in range(200):
        if session.rendering and not session.frame_done:
            time.sleep(0.01)
            continue
        frame = session.redraw(depsgraph, camera, ({SIZE}, {SIZE}))
        if frame is not None and frame.stats["vpl_sets"] not in sets:
            sets.append(frame.stats["vpl_sets"])
        if not session.rendering and sets and sets[-1] == 3:
            break
    report["sets"] = sets
    rows = np.array(session.display.rows).reshape({SIZE}, {SIZE}, 3)[::-1]
    session.release()
    image = scene.render.image_settings
    image.media_type, image.file_format, image.color_depth = "MULTI_LAYER_IMAGE", "OPEN_EXR_MULTILAYER", "32"
    scene.render.filepath = out + ".exr"
    bpy.ops.render.render(write_still=True)
    channels = read_exr_channels(out + ".exr")
    f12 = np.stack([channels[f"ViewLayer.Combined.{{c}}"] for c in "RGB"], axis=-1)
    report["ours_on_main_thread"] = getattr(GLContext._threads, "context", None) is not None
    if mode == "glx":
        report["after"] = gl_state()
    np.savez(out, rows=rows, f12=f12)
    print("REPORT " + json.dumps(report))
""")


@pytest.fixture(scope="module")
def x_display():
    """A real X server (Xvfb, which the set-up installs) on a free display number."""
    server = subprocess.Popen(["Xvfb", "-displayfd", "1", "-nolisten", "tcp", "-screen", "0", "640x480x24"],
                              stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    display = ":" + server.stdout.readline().strip()
    yield display
    server.terminate()
    server.wait(timeout=10)


def run(tmp_path, mode, display=None):
    script = tmp_path / "owner.py"
    script.write_text(SCRIPT)
    environment = {key: value for key, value in os.environ.items() if key not in ("DISPLAY", "WAYLAND_DISPLAY")}
    if display:
        environment["DISPLAY"] = display
    out = tmp_path / mode
    result = subprocess.run([sys.executable, str(script), mode, str(out)], capture_output=True, text=True,
                            env=environment, timeout=300)
    lines = [line for line in result.stdout.splitlines() if line.startswith("REPORT ")]
    assert lines and result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return json.loads(lines[-1][len("REPORT "):]), np.load(f"{out}.npz")


def test_blenders_glx_context_stays_current_and_untouched_while_our_frames_render(x_display, tmp_path):
    report, images = run(tmp_path, "glx", x_display)
    assert report["after"] == report["before"] and report["before"]["context"]
    assert report["before"]["clear"] == [0.25, 0.5, 0.75, 1.0] and report["before"]["viewport"] == [0, 0, 7, 5]
    assert not report["ours_on_main_thread"]
    assert not report["first_redraw_waits"] and report["sets"] == [1, 2, 3]  # redraws never wait for a render
    _, alone = run(tmp_path, "none")
    for name in ("rows", "f12"):
        assert images[name].mean() > 0
        np.testing.assert_allclose(images[name][..., :3], alone[name][..., :3], rtol=1e-4, atol=1e-6)


def test_with_no_display_at_all_frames_render_off_the_main_thread(tmp_path):
    report, images = run(tmp_path, "none")
    assert not report["ours_on_main_thread"] and report["sets"] == [1, 2, 3]
    assert images["rows"].mean() > 0 and images["f12"].mean() > 0
