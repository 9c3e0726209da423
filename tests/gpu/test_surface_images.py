"""Image textures and vertex colours on the GPU (gpu/surface_images.py, shaders/surface.glsl):
the camera sees the image per pixel and the lights' maps reflect it per texel, so a
checker floor renders as a checker and bleeds its own colours, not its average."""
import numpy as np
import pytest

from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.scene import Camera, Light, Scene, SurfaceImage
from lpv_preview.gpu.scene_file import load_scene, save_scene
from lpv_preview.gpu.settings import Settings
from lpv_preview.gpu.surface_images import layer_size, resampled

from .gbuffers import drawn_gbuffer

SETTINGS = Settings(width=64, height=64, rsm_resolution=128, vpls_per_light=512, lpv_resolution=16, method="cm")
RED, GREEN = (0.8, 0.05, 0.05), (0.05, 0.8, 0.05)


def quad(x0, x1, y0, y1, z=0.0):
    a, b, c, d = (x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)
    return [[a, b, c], [a, c, d]]


def wall(x, y0, y1, z0, z1):
    a, b, c, d = (x, y0, z0), (x, y1, z0), (x, y1, z1), (x, y0, z1)
    return [[a, b, c], [a, c, d]]


def halves_image():
    """Red left half, green right half (U < 0.5 red), 64 x 64 pixels, top row first."""
    pixels = np.empty((64, 64, 3), np.float32)
    pixels[:, :32], pixels[:, 32:] = RED, GREEN
    return SurfaceImage("halves", pixels)


def floor_scene(textured=True, vertex_colors=None):
    """A 4 m floor (UV 0..1 across it, red left and green right), a white wall at x = 2,
    a light above, the camera looking down; the floor's albedo is white."""
    triangles = np.array(quad(-2, 2, -2, 2) + wall(2, -2, 2, 0, 3), dtype=np.float32)
    uv = np.array([[(0, 0), (1, 0), (1, 1)], [(0, 0), (1, 1), (0, 1)]] * 2, dtype=np.float32)
    layers = np.array([0, 0, -1, -1] if textured else [-1] * 4, dtype=np.int16)
    light = Light("POINT", (0.0, 0.0, 2.5), (0, 0, -1), (0, 1, 0), (1, 1, 1), 300.0)
    camera = Camera.look_at((0, 0, 7), (0, 0, 0), up=(0, 1, 0), fov_y=np.radians(40), near=0.1, far=20)
    return Scene(triangles, np.zeros_like(triangles), np.ones((4, 3), np.float32), [light], camera,
                 uvs=uv, image_layers=layers, images=[halves_image()] if textured else [],
                 vertex_colors=vertex_colors).sanitize()


@pytest.fixture(scope="module")
def textured(glc):
    return render_once(floor_scene(), SETTINGS, glc).passes


def test_the_camera_sees_the_image_per_pixel(textured):
    direct = textured["direct"]
    left, right = direct[20:44, 10:24].mean(axis=(0, 1)), direct[20:44, 34:46].mean(axis=(0, 1))
    assert left[0] > 5 * left[1] and right[1] > 5 * right[0]  # red left, green right


def test_the_lights_maps_reflect_the_image_per_texel(glc):
    """The light's map holds the floor's red texels and green ones (the white wall's
    beside them), where the floor's average would be yellow everywhere."""
    from lpv_preview.gpu.pipeline import Pipeline
    scene = floor_scene()
    pipeline = Pipeline(SETTINGS, glc)
    try:
        (maps,), _ = pipeline.light_maps(scene)
        flux = maps.rsm.read(maps.rsm.flux)[..., :3].reshape(-1, 3)
    finally:
        pipeline.release()
    lit = flux[flux.sum(axis=1) > 0]
    red = np.mean(lit[:, 0] > 5 * lit[:, 1])
    green = np.mean(lit[:, 1] > 5 * lit[:, 0])
    ratio = lit[:, 0] / np.maximum(lit[:, 1], 1e-12)
    yellow = np.mean((ratio > 0.5) & (ratio < 2) & (lit[:, 0] > 2 * lit[:, 2]))  # what an average would give
    assert red > 0.1 and green > 0.1 and yellow < 0.05 * (red + green)


def test_vertex_colours_multiply_the_albedo(glc):
    colors = np.ones((4, 3, 3), np.float32)
    colors[:2] = (0.1, 0.1, 0.9)  # the floor's corners blue
    direct = render_once(floor_scene(textured=False, vertex_colors=colors), SETTINGS, glc).passes["direct"]
    floor = direct[20:44, 20:44].mean(axis=(0, 1))
    assert floor[2] > 5 * floor[0]


def test_images_resample_to_a_power_of_two_and_keep_their_orientation():
    image = halves_image().pixels[::8, ::8].copy()
    image[:4] *= 0.5  # the top rows darker
    assert layer_size([SurfaceImage("a", np.zeros((600, 300, 3)))]) == 1024
    assert layer_size([SurfaceImage("a", np.zeros((5000, 20, 3)))]) == 1024
    square = resampled(image, 4)
    assert square.shape == (4, 4, 3)
    assert np.allclose(square[:, 0], np.array(RED)[None] * [[1], [1], [0.5], [0.5]])  # bottom row first
    assert np.allclose(resampled(np.ones((4096, 4096, 3)), 16), 1.0)


def test_textured_scenes_save_and_load(tmp_path):
    scene = floor_scene()
    save_scene(scene, tmp_path / "floor.npz")
    loaded = load_scene(tmp_path / "floor.npz").sanitize()
    assert loaded.geometry_key() == scene.geometry_key()
    assert [image.name for image in loaded.images] == ["halves"]


def test_a_surface_bounces_its_texture_mean_colour():
    """The points later bounces and the emitters' bounce light (gpu/emitter_bounce.py) take
    each triangle's colour: albedo x mean vertex colour x its image's mean over what the
    image's alpha keeps: a textured floor bounces the colour it shows, not its albedo's white."""
    scene = floor_scene()
    colours = scene.surface_colours()
    np.testing.assert_allclose(colours[:2], np.tile(np.mean([RED, GREEN], axis=0), (2, 1)), rtol=1e-5)
    np.testing.assert_allclose(colours[2:], 1.0)  # the untextured white wall
    pixels = np.zeros((8, 8, 4), np.float32)
    pixels[:, :2] = (0.2, 0.4, 0.6, 1.0)  # a quarter kept by its alpha; the rest cut out (and black)
    assert np.allclose(SurfaceImage("leaf", pixels).mean_colour(), (0.2, 0.4, 0.6))


def test_a_magnified_image_stays_sharp_where_pixel_quads_cross_a_triangles_edge(glc):
    """Every pixel of a floor of two triangles, its image of eight stripes magnified six
    times, sees the image's nearest level bilinear at its UV, on the triangles' shared
    edge too (llvmpipe sampled a blurred level there when a quad's helper pixels read
    their coordinates from the vertex buffer: shaders/surface.glsl)."""
    pixels = np.repeat(np.linspace(0.05, 0.95, 8, dtype=np.float32)[:, None, None], 8, axis=1).repeat(3, axis=2)
    triangles = np.array(quad(-2, 2, -2, 2), dtype=np.float32)
    uv = np.array([[(0, 0), (1, 0), (1, 1)], [(0, 0), (1, 1), (0, 1)]], dtype=np.float32)
    camera = Camera.look_at((0.3, 0.2, 7), (0.3, 0.2, 0), up=(0, 1, 0), fov_y=np.radians(40), near=0.1, far=20)
    scene = Scene(triangles, np.zeros_like(triangles), np.ones((2, 3), np.float32),
                  [Light("SUN", (0, 0, 5), (0, 0, -1), (0, 1, 0), (1, 1, 1), 3.0)], camera, uvs=uv,
                  image_layers=np.zeros(2, np.int16), images=[SurfaceImage("stripes", pixels)]).sanitize()
    record = drawn_gbuffer(glc, scene, (64, 64))
    layer = resampled(pixels, layer_size(scene.images))[..., 0]
    size = layer.shape[0]
    rows, columns = np.nonzero(record.seen)
    points = record.position[rows, columns]
    v = (points[:, 1] + 2) / 4 * size - 0.5  # the image's rows run along y; the floor is uniform along x
    low = np.floor(v).astype(int)
    f = v - low
    expected = (1 - f) * layer[np.mod(low, size), 0] + f * layer[np.mod(low + 1, size), 0]
    assert len(rows) > 1000
    np.testing.assert_allclose(record.albedo[rows, columns, 0], expected, atol=2e-3)
