"""What the raster passes cost on the GPU, and how much of it is the raster itself: for
each scene (time_viewport_work.py's names) at 1920×1080, the median wall-clock
milliseconds (GPU finished before and after) of the camera's G-buffer and a point light's
cube map (512², six faces), each beside a draw of the same culled triangles that writes
only their numbers (the floor a visibility buffer would reach), and the light's DPM
hemispheres (256² and 512², the rim split included) and WDPM's (512², the warp at the
defaults included), whose share of the cube map's is the thesis's figure.

    python scripts/time_raster_passes.py DIR [room1200k ...] [--repeats 30]
"""
import argparse
import math
import statistics
import time

import moderngl
import numpy as np

from lpv_preview.bench.synthetic import scene_by_name
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.rsm import cube_faces, render_rsm
from lpv_preview.gpu.scene import look_at_view, perspective
from lpv_preview.gpu.settings import Settings
from lpv_preview.gpu.shade import render_gbuffer
from lpv_preview.gpu.warp import warp_paraboloid_map

SIZE = (1920, 1080)
NUMBERS_ONLY = ("""#version 450 core
in vec3 in_position;
uniform mat4 view_projection;
flat out int triangle;
void main() { triangle = gl_VertexID / 3; gl_Position = view_projection * vec4(in_position, 1.0); }""",
                """#version 450 core
flat in int triangle;
layout(location = 0) out uint number;
void main() { number = uint(triangle) + 1u; }""")


def median_ms(gl, work, repeats):
    times = []
    for _ in range(repeats):
        gl.finish()
        start = time.perf_counter()
        work()
        gl.finish()
        times.append((time.perf_counter() - start) * 1000)
    return round(statistics.median(times), 2), round(min(times), 2), round(max(times), 2)


def warped_map(glc, mesh, light, bounds, settings):
    """WDPM's map of `light` at 512² as the pipeline makes it: DPM's, then the warp."""
    rsm = render_rsm(glc, mesh, light, 512, bounds, "dpm")
    warped, status = warp_paraboloid_map(glc, rsm, settings.warp_alpha, settings.warp_iterations,
                                         settings.warp_significant_figures)
    for texture in (rsm, warped, status):
        texture.release()


def main():
    parser = argparse.ArgumentParser(description="the raster passes against drawing triangle numbers only")
    parser.add_argument("folder")
    parser.add_argument("names", nargs="*", default=["room1200k"])
    parser.add_argument("--repeats", type=int, default=30)
    args = parser.parse_args()
    for name in args.names:
        scene = scene_by_name(args.folder, name)
        settings = Settings(width=SIZE[0], height=SIZE[1])
        pipeline = Pipeline(settings)
        pipeline.render(scene, passes=())
        glc, gl, mesh, targets = pipeline.glc, pipeline.glc.gl, pipeline._mesh.value, pipeline.targets
        numbers = gl.program(vertex_shader=NUMBERS_ONLY[0], fragment_shader=NUMBERS_ONLY[1])
        image = gl.framebuffer([gl.texture(SIZE, 1, dtype="u4")], gl.depth_texture(SIZE))
        atlas = gl.framebuffer([gl.texture((1536, 1024), 1, dtype="u4")], gl.depth_texture((1536, 1024)))

        def numbers_drawn(framebuffer, views, triangles, resolution=None):
            framebuffer.use()
            framebuffer.clear(depth=1.0)
            gl.enable(moderngl.DEPTH_TEST)
            for face, matrix in enumerate(views):
                framebuffer.viewport = (0, 0, *SIZE) if resolution is None else \
                    ((face % 3) * resolution, (face // 3) * resolution, resolution, resolution)
                numbers["view_projection"].write(np.asarray(matrix, np.float32).T.tobytes())
                mesh.draw(numbers, moderngl.TRIANGLES, triangles, matrix)

        camera = scene.camera
        rows = {"G-buffer": median_ms(gl, lambda: render_gbuffer(glc, mesh, camera, targets), args.repeats),
                "G-buffer, numbers only": median_ms(gl, lambda: numbers_drawn(
                    image, [camera.projection @ camera.view], mesh.camera_triangles), args.repeats)}
        lights = [light for light in scene.lights if light.kind == "POINT"]
        if lights:
            light, bounds = lights[0], scene.bounds()
            corners = np.array([[x, y, z] for x in (bounds[0][0], bounds[1][0]) for y in (bounds[0][1], bounds[1][1])
                                for z in (bounds[0][2], bounds[1][2])])
            far = float(np.max(np.linalg.norm(corners - light.position, axis=1))) * 1.01
            faces = [perspective(math.pi / 2, 1.0, far * 1e-5, far) @ look_at_view(light.position, forward, up)
                     for forward, up in cube_faces(light)]
            rows["cube map 512²"] = median_ms(gl, lambda: render_rsm(glc, mesh, light, 512, bounds, "cm").release(),
                                              args.repeats)
            rows["cube map 512², numbers only"] = median_ms(
                gl, lambda: numbers_drawn(atlas, faces, mesh.light_triangles, 512), args.repeats)
            rows["DPM hemispheres 256²"] = median_ms(
                gl, lambda: render_rsm(glc, mesh, light, 256, bounds, "dpm").release(), args.repeats)
            rows["DPM hemispheres 512²"] = median_ms(
                gl, lambda: render_rsm(glc, mesh, light, 512, bounds, "dpm").release(), args.repeats)
            rows["WDPM hemispheres 512² + warp"] = median_ms(gl, lambda: warped_map(glc, mesh, light, bounds, settings),
                                                             args.repeats)
        print(f"{name} ({mesh.triangle_count:,} triangles, {glc.renderer}):", flush=True)
        for row, (median, least, most) in rows.items():
            print(f"  {row:30s} {median:7.2f} ms ({least:.2f}-{most:.2f})", flush=True)
        pipeline.release()


if __name__ == "__main__":
    main()
