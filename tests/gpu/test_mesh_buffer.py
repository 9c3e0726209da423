"""gpu/mesh_buffer.py: the scene's arrays interleaved into the vertex buffer on the GPU
(shaders/mesh_interleave.comp) hold each vertex as VERTEX_LAYOUT says, every surface
array given or left out."""
import numpy as np
import pytest

from lpv_preview.gpu.mesh_buffer import VERTEX_FLOATS, VERTEX_SLICES, MeshBuffer
from lpv_preview.gpu.scene import Camera, Light, Scene

from .gbuffers import drawn_gbuffer

LAMP = Light("POINT", (0.0, 0.0, 3.0), (0, 0, -1), (0, 1, 0), (1, 1, 1), 10.0)


def random_scene(rng, count, every_array):
    triangles = rng.uniform(-1, 1, (count, 3, 3)).astype(np.float32)
    arrays = {}
    if every_array:
        arrays = {"vertex_colors": rng.uniform(0, 1, (count, 3, 3)), "alpha": rng.uniform(0.3, 1, count),
                  "transmission": np.concatenate([rng.uniform(0, 1, (count, 3)), rng.uniform(0, 0.9, (count, 1))], 1),
                  "uvs": rng.uniform(0, 1, (count, 3, 2)), "image_layers": rng.integers(-1, 3, count),
                  "alpha_layers": rng.integers(-1, 3, count), "specular": rng.uniform(0, 1, (count, 5))}
        arrays = {name: array.astype(np.float32 if array.dtype.kind == "f" else np.int16) for name, array in arrays.items()}
    return Scene(triangles, rng.normal(size=(count, 3, 3)).astype(np.float32),
                 rng.uniform(0, 1, (count, 3)).astype(np.float32), [LAMP],
                 Camera.look_at((0, -5, 0), (0, 0, 0)), **arrays)


def vertices(glc, scene):
    mesh = MeshBuffer(glc, scene)
    try:
        return np.frombuffer(mesh.buffer.read(), np.float32).reshape(scene.triangle_count, 3, VERTEX_FLOATS)
    finally:
        mesh.release()


def test_every_surface_array_lands_in_its_vertex_floats(glc):
    rng = np.random.default_rng(5)
    scene = random_scene(rng, 300, every_array=True)  # unsanitized: sanitize drops UVs without images
    found = {name: vertices(glc, scene)[..., where] for name, where in VERTEX_SLICES.items()}
    np.testing.assert_array_equal(found["in_position"], scene.triangles)
    np.testing.assert_array_equal(found["in_normal"], scene.normals)
    opaque = np.maximum(1.0 - scene.transmission[:, 3], 1e-6)[:, None, None]
    albedo = np.clip(scene.albedo[:, None, :] * scene.vertex_colors / opaque, 0.0, 1.0)
    np.testing.assert_allclose(found["in_albedo"][..., :3], albedo, rtol=1e-6)
    np.testing.assert_array_equal(found["in_albedo"][..., 3], np.repeat(scene.alpha[:, None], 3, 1))
    np.testing.assert_array_equal(found["in_surface"][..., :2], scene.uvs)
    np.testing.assert_array_equal(found["in_surface"][..., 2], np.repeat(scene.image_layers[:, None], 3, 1))
    np.testing.assert_array_equal(found["in_surface"][..., 3], np.repeat(scene.alpha_layers[:, None], 3, 1))
    np.testing.assert_array_equal(found["in_transmission"], np.repeat(scene.transmission[:, None], 3, 1))
    np.testing.assert_array_equal(found["in_specular"], np.repeat(scene.specular[:, None, :4], 3, 1))
    np.testing.assert_array_equal(found["in_metallic"][..., 0], np.repeat(scene.specular[:, None, 4], 3, 1))


def test_a_scene_without_surface_arrays_gets_their_defaults(glc):
    scene = random_scene(np.random.default_rng(6), 2000, every_array=False)
    scene.sanitize()
    found = vertices(glc, scene)
    np.testing.assert_array_equal(found[..., VERTEX_SLICES["in_position"]], scene.triangles)
    np.testing.assert_array_equal(found[..., VERTEX_SLICES["in_albedo"]][..., :3],
                                  np.repeat(scene.albedo[:, None], 3, 1))
    defaults = np.array([1, 0, 0, -1, -1, 1, 1, 1, 0, 0, 0, 0, 1, 0], np.float32)  # alpha, uv, layers, tint, F0, ...
    np.testing.assert_array_equal(found[..., 9:], np.broadcast_to(defaults, found[..., 9:].shape))


@pytest.mark.parametrize("orthographic", [False, True])
def test_each_pixel_sees_the_corners_mixed_where_its_ray_meets_the_triangle(glc, orthographic):
    """The G-buffer's triangle numbers and the resolve of the surface from them
    (shaders/gbuffer.frag, gbuffer_resolve.comp): a triangle seen obliquely in
    perspective (or by an orthographic camera), its corners red, green and blue, gives
    each pixel the corners' colours weighted where the pixel's ray meets it, as
    perspective-correct interpolation does; the pixels that see the tip of a second
    triangle get that one's colour."""
    triangles = np.array([[(-3, 0, 0), (3, 0, 0), (0, 9, 0)], [(-0.2, 2, 0.5), (0.2, 2, 0.5), (0, 2.3, 0.5)]],
                         dtype=np.float32)
    normals = np.tile(np.float32([0, 0, 1]), (2, 3, 1))
    colours = np.array([np.eye(3), np.full((3, 3), 0.5)], dtype=np.float32)
    camera = Camera.look_at((0.5, -3, 2), (0, 4, 0), aspect=4 / 3)
    if orthographic:  # 6 m across
        camera = Camera(camera.view, np.diag([1 / 3, 1 / 2.25, -2 / 19.9, 1.0]) + np.array(
            [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, -20.1 / 19.9], [0, 0, 0, 0]]))
    scene = Scene(triangles, normals, np.ones((2, 3), np.float32), [LAMP], camera, vertex_colors=colours).sanitize()
    assert not np.any(scene.world_origin)
    record = drawn_gbuffer(glc, scene, (64, 48))
    rows, columns = np.nonzero(record.seen)
    inverse = np.linalg.inv(camera.projection @ camera.view)
    ndc = np.stack([(columns + 0.5) / 32 - 1, 1 - (rows + 0.5) / 24, np.full(len(rows), -1.0), np.ones(len(rows))])
    near, far = inverse @ ndc, inverse @ (ndc * [[1], [1], [-1], [1]])
    origin = (near[:3] / near[3]).T
    direction = (far[:3] / far[3]).T - origin
    t = -origin[:, 2] / direction[:, 2]  # the first triangle lies in z = 0
    hit = origin + t[:, None] * direction
    p0, e1, e2 = triangles[0, 0], triangles[0, 1] - triangles[0, 0], triangles[0, 2] - triangles[0, 0]
    weights = np.linalg.lstsq(np.stack([e1, e2], axis=1), (hit - p0).T, rcond=None)[0].T
    expected = np.stack([1 - weights.sum(axis=1), weights[:, 0], weights[:, 1]], axis=1)  # red, green, blue
    found = record.albedo[rows, columns]
    on_tip = np.all(np.isclose(found, 0.5, atol=1e-4), axis=1)
    assert 0 < on_tip.sum() < 20
    assert len(rows) > 500
    np.testing.assert_allclose(found[~on_tip], expected[~on_tip], atol=2e-4)
