"""A light grid cluster's square (shaders/emitter.glsl square_faces) against numerical
integration, and a lattice of squares against the lit plane they tile."""
import math

import numpy as np

from ..glsl import evaluate

FACES = """
Emitter square(vec3 normal) { return Emitter(vec4(0.0, 0.0, 0.0, 1.0), vec4(normal, 1.0), vec4(vec3(PI), 0.0)); }
// +x, +y, +z and -x, -y, -z of the unit square facing +z (radiance 1) at p
vec4 plus_at(vec3 p) { vec3 light, plus, minus; square_faces(square(vec3(0, 0, 1)), p, light, plus, minus); return vec4(light.r * plus, 0.0); }
vec4 minus_at(vec3 p) { vec3 light, plus, minus; square_faces(square(vec3(0, 0, 1)), p, light, plus, minus); return vec4(light.r * minus, 0.0); }
// the unit square's flux standing for no area
vec4 no_area_down(vec3 p) {
    Emitter e = square(vec3(0, 0, 1));
    e.normal.w = 0.0;
    vec3 light, plus, minus;
    square_faces(e, p, light, plus, minus);
    return vec4(light.r * minus.z, 0.0, 0.0, 0.0);
}
// the unit area's flux as a point with r^2 grown by the area of its cluster's disk (emitter.glsl emitter_light)
vec4 disk_down(vec3 p, float disk_area) {
    Emitter e = square(vec3(0, 0, 1));
    e.normal.w = disk_area;
    return vec4(emitter_light(e, p) * max(0.0, normalize(p).z), 0.0);
}
"""
INCLUDES = ("common.glsl", "emitter.glsl")
SIDES = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 0], [0, -1, 0], [0, 0, -1]], dtype=float)


def integrated_faces(p, samples=240):
    """The irradiance at p of the unit square at the origin facing +z, radiance 1, on
    surfaces facing +x, +y, +z, -x, -y, -z: the midpoint rule over the square."""
    g = (np.arange(samples) + 0.5) / samples - 0.5
    points = np.stack(np.meshgrid(g, g, indexing="ij") + [np.zeros((samples, samples))], -1).reshape(-1, 3)
    to = points - p
    r = np.linalg.norm(to, axis=1)
    emitted = np.clip(-to[:, 2] / r, 0.0, None)
    return np.array([(emitted * np.clip(to @ side / r, 0.0, None) / r ** 2).sum() / samples ** 2 for side in SIDES])


def test_each_face_of_a_near_square_is_lit_as_integration_says(glc):
    rng = np.random.default_rng(5)
    receivers = np.column_stack([rng.uniform(-1.0, 1.0, (128, 2)), rng.uniform(0.05, 1.2, 128)])  # within 2 sides
    plus, minus = evaluate(glc, INCLUDES, ["plus_at(x.xyz)", "minus_at(x.xyz)"], receivers, FACES)
    ours = np.concatenate([plus[:, :3], minus[:, :3]], axis=1)
    expected = np.array([integrated_faces(p) for p in receivers])
    np.testing.assert_allclose(ours, expected, rtol=0.01, atol=2e-3)


def test_a_square_lights_nothing_behind_it(glc):
    receivers = np.array([[0.2, 0.1, -0.3], [2.0, 0.0, -0.01], [0.0, 0.0, -5.0]] * 22)[:64]
    plus, minus = evaluate(glc, INCLUDES, ["plus_at(x.xyz)", "minus_at(x.xyz)"], receivers, FACES)
    assert not plus.any() and not minus.any()


def test_far_squares_are_points(glc):
    """Beyond two sides the net light along each axis (plus face less minus face) is
    within 3 % of the light a receiver gets."""
    receivers = np.array([[3.0 * math.cos(a), 2.0 * math.sin(a), 2.5] for a in np.linspace(0, 6, 64)])
    plus, minus = evaluate(glc, INCLUDES, ["plus_at(x.xyz)", "minus_at(x.xyz)"], receivers, FACES)
    expected = np.array([integrated_faces(p, 120) for p in receivers])
    net = plus[:, :3] - minus[:, :3]
    expected_net = expected[:, :3] - expected[:, 3:]
    assert (np.abs(net - expected_net) < 0.03 * expected.max(axis=1, keepdims=True)).all()


def test_a_cluster_of_no_area_is_a_point(glc):
    receivers = np.column_stack([np.linspace(-1e-3, 2.0, 64), np.zeros(64), np.linspace(1e-4, 1.0, 64)])
    lit = evaluate(glc, INCLUDES, ["no_area_down(x.xyz)"], receivers, FACES)[0]
    r2 = (receivers ** 2).sum(axis=1)
    np.testing.assert_allclose(lit[:, 0], receivers[:, 2] ** 2 / r2 ** 2, rtol=1e-4)  # pi cos cos / (pi r^2)
    assert np.isfinite(lit).all()


def integrated_region(p, half_width, step=0.02):
    """The irradiance at p of the square [-half_width, half_width]² at z = 0, radiance 1,
    on surfaces facing +x, +y and -z: the midpoint rule."""
    g = np.arange(-half_width + step / 2, half_width, step)
    x, y = np.meshgrid(g, g, indexing="ij")
    to = np.stack([x - p[0], y - p[1], np.full_like(x, -p[2])], -1)
    r2 = (to ** 2).sum(-1)
    emitted = p[2] / np.sqrt(r2)
    return np.array([(emitted * np.clip(to[..., axis] * sign, 0.0, None) / np.sqrt(r2) / r2).sum() * step * step
                     for axis, sign in ((0, 1.0), (1, 1.0), (2, -1.0))])


def lattice_light(glc, expression, heights, offsets, half_width=30):
    """What a lattice of unit squares tiling z = 0 (2 half_width + 1 a side) gives each
    receiver at (offset, height) through `expression` of the receiver relative to a square."""
    k = np.arange(-half_width, half_width + 1)
    cells = np.stack(np.meshgrid(k, k, indexing="ij"), -1).reshape(-1, 2)
    sums = {}
    for height in heights:
        for offset in offsets:
            receivers = np.column_stack([offset[0] - cells[:, 0], offset[1] - cells[:, 1], np.full(len(cells), height)])
            padded = np.zeros((-(-len(receivers) // 64) * 64, 3))
            padded[:len(receivers)] = receivers
            padded[len(receivers):, 2] = -1.0  # behind the squares: no light
            sums[height, offset] = evaluate(glc, INCLUDES, [expression], padded, FACES)[0, :, :3].sum(axis=0)
    return sums


def test_a_lattice_of_squares_gives_the_plane_wherever_the_receiver_falls(glc):
    """A cell centre a quarter of a side or more over a lit plane gets the plane's light on each
    face within 2.5 % (the neighbours beyond two sides are points), between the squares'
    centres as well as over them. Printed beside it: the clusters
    as points bounded by their cells' disk (the light grid before its squares) give a
    fraction of that."""
    offsets = ((0.0, 0.0), (0.5, 0.0), (0.5, 0.5), (0.25, 0.1))
    heights = (0.25, 0.75, 1.5)  # the light grid's first cell centres: half a cell and more, the squares two cells wide
    half_width = 12
    squares = lattice_light(glc, "minus_at(x.xyz)", heights, offsets, half_width)
    across = lattice_light(glc, "plus_at(x.xyz)", heights, offsets, half_width)
    disks = lattice_light(glc, "disk_down(x.xyz, PI / 4.0)", heights, offsets, half_width)
    for height in heights:
        plane = {offset: integrated_region((*offset, height), half_width + 0.5) for offset in offsets}
        for offset in offsets:
            np.testing.assert_allclose(squares[height, offset][2], plane[offset][2], rtol=0.025)
            np.testing.assert_allclose(across[height, offset][:2], plane[offset][:2], rtol=0.025)
        print(f"height {height}: squares {[round(squares[height, o][2] / plane[o][2], 3) for o in offsets]} of the "
              f"plane, points with the disk bound {[round(disks[height, o][2] / plane[o][2], 3) for o in offsets]}")
