"""addon/extract.py against real Blender scenes: instancing, modifiers, materials,
visibility, lights, camera, broken geometry, and the speed of a million triangles.

Each scene is built once per module; fixtures hand back extracted data, never live bpy
state, so tests do not depend on which scene Blender holds at the moment.
"""
import math
import time

import bpy
import numpy as np
import pytest
from mathutils import Matrix

from lpv_preview.addon.extract import extract_scene, render_resolution
from lpv_preview.gpu.errors import LPVError
from lpv_preview.gpu.scene_file import load_scene, save_scene

CELL = 10.0  # every test object sits in its own 10 m cell along x
RED = (0.9, 0.1, 0.05)
GREEN = (0.1, 0.7, 0.2)
PROP = (0.3, 0.4, 0.5)
MIX_FACTOR = 0.25
IMAGE_SRGB = (0.2, 0.8)  # the two pixel values of the test texture, sRGB-encoded


def srgb_to_linear(value):
    return value / 12.92 if value <= 0.04045 else ((value + 0.055) / 1.055) ** 2.4


def reset_blender():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


def mesh_object(name, vertices, faces, location=(0, 0, 0), collection=None, materials=()):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    for material in materials:
        mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    (collection or bpy.context.scene.collection).objects.link(obj)
    return obj


def unit_quad(name, location=(0, 0, 0), collection=None, materials=()):
    return mesh_object(name, [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [(0, 1, 2, 3)], location, collection,
                       materials)


def cube_object(name, location, size=2.0, collection=None):
    s = size / 2
    corners = [(x, y, z) for x in (-s, s) for y in (-s, s) for z in (-s, s)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return mesh_object(name, corners, faces, location, collection)


def beveled_curve():
    """A 3 m straight curve with a round bevel: a tube."""
    curve = bpy.data.curves.new("Tube", "CURVE")
    curve.dimensions, curve.bevel_depth = "3D", 0.2
    spline = curve.splines.new("POLY")
    spline.points.add(1)
    spline.points[1].co = (3, 0, 0, 1)
    return curve


def light_object(name, kind, location=(0, 0, 0), rotation=(0, 0, 0), scale=(1, 1, 1), **settings):
    light = bpy.data.lights.new(name, kind)
    for key, value in settings.items():
        setattr(light, key, value)
    obj = bpy.data.objects.new(name, light)
    obj.location, obj.rotation_euler, obj.scale = location, rotation, scale
    bpy.context.scene.collection.objects.link(obj)
    return obj


def principled(name, color):
    material = bpy.data.materials.new(name)
    material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (*color, 1)
    return material


def diffuse(name, color):
    """A Diffuse BSDF feeding the output through a reroute."""
    material = bpy.data.materials.new(name)
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.remove(nodes["Principled BSDF"])
    shader = nodes.new("ShaderNodeBsdfDiffuse")
    shader.inputs["Color"].default_value = (*color, 1)
    reroute = nodes.new("NodeReroute")
    links.new(shader.outputs[0], reroute.inputs[0])
    links.new(reroute.outputs[0], nodes["Material Output"].inputs["Surface"])
    return material


def mixed_red_green():
    """A quarter green, three quarters red through a Mix Shader."""
    material = principled("Mix", RED)
    nodes, links = material.node_tree.nodes, material.node_tree.links
    green = nodes.new("ShaderNodeBsdfDiffuse")
    green.inputs["Color"].default_value = (*GREEN, 1)
    mix = nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = MIX_FACTOR
    links.new(nodes["Principled BSDF"].outputs[0], mix.inputs[1])
    links.new(green.outputs[0], mix.inputs[2])
    links.new(mix.outputs[0], nodes["Material Output"].inputs["Surface"])
    return material


def textured(name):
    """A Principled BSDF whose base colour comes from a 2x1 byte image (sRGB)."""
    image = bpy.data.images.new(name, 2, 1)
    image.pixels.foreach_set(np.array([[v, v, v, 1.0] for v in IMAGE_SRGB], dtype=np.float32).ravel())
    material = bpy.data.materials.new(name)
    texture = material.node_tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    material.node_tree.links.new(texture.outputs["Color"],
                                 material.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
    return material


def instance_on_points(host, instanced):
    """A geometry-nodes modifier that puts `instanced` on every vertex of `host`."""
    tree = bpy.data.node_groups.new("Instance on points", "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    group_in, group_out = tree.nodes.new("NodeGroupInput"), tree.nodes.new("NodeGroupOutput")
    instancer = tree.nodes.new("GeometryNodeInstanceOnPoints")
    info = tree.nodes.new("GeometryNodeObjectInfo")
    info.inputs["Object"].default_value = instanced
    tree.links.new(group_in.outputs[0], instancer.inputs["Points"])
    tree.links.new(info.outputs["Geometry"], instancer.inputs["Instance"])
    tree.links.new(instancer.outputs[0], group_out.inputs[0])
    host.modifiers.new("Instances", "NODES").node_group = tree


class CaptureEngine(bpy.types.RenderEngine):
    """A render engine whose render() only extracts, to get a render-mode depsgraph."""

    bl_idname = "LPV_TEST_CAPTURE"
    bl_label = "LPV test capture"
    captured = {}

    def render(self, depsgraph):
        try:
            CaptureEngine.captured["scene"] = extract_scene(depsgraph)
            CaptureEngine.captured["mode"] = depsgraph.mode
        except Exception as error:  # render() swallows exceptions; hand it to the test
            CaptureEngine.captured["error"] = error


def extract_for_render(scene):
    bpy.utils.register_class(CaptureEngine)
    try:
        CaptureEngine.captured.clear()
        scene.render.engine = CaptureEngine.bl_idname
        bpy.ops.render.render()
    finally:
        bpy.utils.unregister_class(CaptureEngine)
    if "error" in CaptureEngine.captured:
        raise CaptureEngine.captured["error"]
    return CaptureEngine.captured


def in_cell(scene, cell):
    """Indices of the triangles whose centroid lies in the given 10 m cell along x."""
    x = scene.triangles[:, :, 0].mean(axis=1)
    return np.flatnonzero((x >= cell * CELL - 1) & (x < (cell + 1) * CELL - 1))


@pytest.fixture(scope="module")
def mixed():
    """One scene with every kind of thing extraction must handle, extracted three ways:
    viewport depsgraph, render depsgraph, and a viewport in local view."""
    scene = reset_blender()
    unit_quad("Plain", (0 * CELL, 0, 0))
    arrayed = unit_quad("Arrayed", (1 * CELL, 0, 0))
    array = arrayed.modifiers.new("Array", "ARRAY")
    array.count, array.relative_offset_displace = 3, (1, 0, 0)
    striped = mesh_object("Striped", [(x, y, 0) for x in range(5) for y in (0, 1)],
                          [(0, 2, 3, 1), (2, 4, 5, 3), (4, 6, 7, 5), (6, 8, 9, 7)], (2 * CELL, 0, 0),
                          materials=[principled("Red", RED), diffuse("Green", GREEN), textured("Texture"),
                                     mixed_red_green()])
    striped.data.polygons.foreach_set("material_index", [0, 1, 2, 3])
    props = bpy.data.collections.new("Props")
    prop = unit_quad("Prop", collection=props, materials=[principled("Prop", PROP)])
    instancer = bpy.data.objects.new("Props instance", None)
    instancer.instance_type, instancer.instance_collection = "COLLECTION", props
    instancer.location, instancer.scale = (3 * CELL, 0, 0), (2, 2, 2)
    scene.collection.objects.link(instancer)
    host = mesh_object("Points", [(0, 0, 0), (2, 0, 0), (4, 0, 0)], [], (4 * CELL, 0, 0))
    instance_on_points(host, prop)
    unit_quad("Hidden", (5 * CELL, 0, 0)).hide_set(True)
    unit_quad("Not rendered", (6 * CELL, 0, 0)).hide_render = True
    unit_quad("Mirrored", (7 * CELL, 0, 0)).scale = (-1, 1, 1)
    cube_object("Flat cube", (8 * CELL, 0, 0))
    cube_object("Smooth cube", (9 * CELL, 0, 0)).data.shade_smooth()
    tilted = unit_quad("Tilted", (10 * CELL, 0, 0))
    tilted.rotation_euler, tilted.scale = (math.radians(45), 0, math.radians(30)), (1, 3, 0.5)
    curve = bpy.data.objects.new("Beveled curve", beveled_curve())
    curve.location = (11 * CELL, 0, 0)
    scene.collection.objects.link(curve)
    scene.collection.objects.link(bpy.data.objects.new("Empty mesh", bpy.data.meshes.new("Empty mesh")))

    light_object("Point", "POINT", (0, 0, 5), energy=100, exposure=1.0, shadow_soft_size=0.2)
    light_object("Spot", "SPOT", (1, 2, 3), (math.radians(90), 0, 0), energy=50, spot_size=0.8, spot_blend=0.3,
                 use_temperature=True, temperature=3000, color=(1.0, 0.5, 0.25))
    light_object("Area", "AREA", (0, 0, 4), scale=(2, 1, 1), energy=10, shape="RECTANGLE", size=2.0, size_y=0.5,
                 normalize=False)
    light_object("Disk", "AREA", (0, 0, 4), energy=4, shape="DISK", size=2.0, normalize=False)
    light_object("Normalized", "AREA", (0, 0, 4), energy=7, shape="SQUARE", size=3.0)
    light_object("Sun", "SUN", (0, 0, 9), (math.radians(30), 0, math.radians(60)), energy=3)

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location, camera.rotation_euler = (0, -10, 5), (math.radians(70), 0, 0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 400, 200, 50

    depsgraph = bpy.context.evaluated_depsgraph_get()
    viewport = extract_scene(depsgraph)
    curve_mesh = curve.evaluated_get(depsgraph).to_mesh()
    curve_triangles = len(curve_mesh.loop_triangles)
    curve.evaluated_get(depsgraph).to_mesh_clear()
    expected_projection = np.array(camera.calc_matrix_camera(depsgraph, x=200, y=100))
    square = extract_scene(depsgraph, resolution=(100, 100))
    expected_view = np.array(camera.matrix_world.inverted())
    spot_color = np.array(bpy.data.lights["Spot"].temperature_color) * (1.0, 0.5, 0.25)
    render = extract_for_render(scene)

    screen = bpy.data.screens["Layout"]
    area = next(area for area in screen.areas if area.type == "VIEW_3D")
    region = next(region for region in area.regions if region.type == "WINDOW")
    for obj in scene.objects:
        obj.select_set(obj.name in ("Plain", "Point"))
    with bpy.context.temp_override(screen=screen, area=area, region=region, space_data=area.spaces.active):
        bpy.ops.view3d.localview()
    local = extract_scene(bpy.context.evaluated_depsgraph_get(), view3d=area.spaces.active)
    return {"viewport": viewport, "square": square, "render": render, "local": local,
            "curve_triangles": curve_triangles, "expected_projection": expected_projection,
            "expected_view": expected_view, "spot_color": spot_color}


def test_triangle_counts_per_object(mixed):
    scene = mixed["viewport"]
    counts = [len(in_cell(scene, cell)) for cell in range(11)]
    # plain, array x3, three stripes, collection instance, three geometry-nodes instances,
    # hidden, not rendered (visible in the viewport), mirrored, two cubes, tilted
    assert counts == [2, 6, 8, 2, 6, 0, 2, 2, 12, 12, 2]
    assert scene.triangle_count == sum(counts) + mixed["curve_triangles"]
    assert scene.dropped == {"non_finite": 0, "zero_area": 0}


def test_curves_count_once(mixed):
    """A curve object's mesh arrives as its own instance; the curve itself adds nothing."""
    assert mixed["curve_triangles"] > 0
    assert len(in_cell(mixed["viewport"], 11)) == mixed["curve_triangles"]


def test_render_depsgraph_follows_render_visibility(mixed):
    """A render leaves out what is disabled in renders, and shows what is only hidden in
    the viewport."""
    assert mixed["render"]["mode"] == "RENDER"
    render = mixed["render"]["scene"]
    assert len(in_cell(render, 5)) == 2
    assert len(in_cell(render, 6)) == 0
    assert render.triangle_count == mixed["viewport"].triangle_count


def test_local_view_shows_only_its_objects(mixed):
    local = mixed["local"]
    assert local.triangle_count == 2 and len(in_cell(local, 0)) == 2
    assert [light.name for light in local.lights] == ["Point"]


def has_vertex(scene, cell, point):
    corners = scene.triangles[in_cell(scene, cell)].reshape(-1, 3)
    return bool(np.any(np.all(np.abs(corners - np.asarray(point)) < 1e-5, axis=1)))


def test_world_positions_of_known_vertices(mixed):
    scene = mixed["viewport"]
    assert has_vertex(scene, 0, (1, 1, 0))
    assert has_vertex(scene, 1, (CELL + 3, 1, 0))  # far corner of the third array copy
    assert not has_vertex(scene, 1, (CELL + 4, 1, 0))
    assert has_vertex(scene, 3, (3 * CELL + 2, 2, 0))  # the instance is scaled by 2
    for point_x in (0, 2, 4):  # one prop per host vertex
        assert has_vertex(scene, 4, (4 * CELL + point_x + 1, 1, 0))
    assert has_vertex(scene, 7, (7 * CELL - 1, 1, 0))  # mirrored in x


def test_albedo_per_material_slot(mixed):
    scene = mixed["viewport"]
    plain = scene.albedo[in_cell(scene, 0)]
    np.testing.assert_allclose(plain, 0.8, atol=1e-6)
    for cell in (3, 4):  # collection and geometry-nodes instances keep the prop's material
        np.testing.assert_allclose(scene.albedo[in_cell(scene, cell)], np.tile(PROP, (len(in_cell(scene, cell)), 1)),
                                   atol=1e-6)
    stripes = scene.albedo[in_cell(scene, 2)]
    x = scene.triangles[in_cell(scene, 2), :, 0].mean(axis=1) - 2 * CELL
    texture = np.mean([srgb_to_linear(v) for v in IMAGE_SRGB])
    mix = (1 - MIX_FACTOR) * np.array(RED) + MIX_FACTOR * np.array(GREEN)
    for stripe, color in enumerate((RED, GREEN, (texture,) * 3, mix)):
        np.testing.assert_allclose(stripes[(x > stripe) & (x < stripe + 1)], np.tile(color, (2, 1)), atol=1e-5)


def geometric_normals(triangles):
    cross = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    return cross / np.linalg.norm(cross, axis=1, keepdims=True)


def test_flat_normals_match_the_transformed_faces(mixed):
    """Flat faces: every corner normal equals the world-space face normal, which checks
    the inverse-transpose normal transform (tilted, non-uniformly scaled quad) and the
    winding fix for mirrored objects."""
    scene = mixed["viewport"]
    flat = np.concatenate([in_cell(scene, cell) for cell in (0, 1, 3, 4, 7, 8, 10)])
    faces = geometric_normals(scene.triangles[flat].astype(np.float64))
    np.testing.assert_allclose(scene.normals[flat], np.repeat(faces[:, None], 3, axis=1), atol=1e-5)
    np.testing.assert_allclose(scene.normals[in_cell(scene, 7)], np.tile((0, 0, 1), (2, 3, 1)), atol=1e-6)


def test_smooth_normals_follow_the_vertices(mixed):
    scene = mixed["viewport"]
    cube = in_cell(scene, 9)
    corners = scene.triangles[cube] - (9 * CELL, 0, 0)
    np.testing.assert_allclose(scene.normals[cube], corners / math.sqrt(3), atol=1e-5)


def test_lights(mixed):
    lights = {light.name: light for light in mixed["viewport"].lights}
    assert set(lights) == {"Point", "Spot", "Area", "Disk", "Normalized", "Sun"}
    point = lights["Point"]
    assert point.kind == "POINT" and point.power == pytest.approx(200.0) and point.radius == pytest.approx(0.2)
    np.testing.assert_allclose(point.position, (0, 0, 5))
    spot = lights["Spot"]
    assert spot.kind == "SPOT" and spot.spot_size == pytest.approx(0.8) and spot.spot_blend == pytest.approx(0.3)
    np.testing.assert_allclose(spot.color, mixed["spot_color"], rtol=1e-6)
    assert spot.color[0] > spot.color[2]  # 3000 K is warm
    np.testing.assert_allclose(spot.direction, (0, 1, 0), atol=1e-6)  # -Z turned 90° about x
    np.testing.assert_allclose(spot.up, (0, 0, 1), atol=1e-6)
    area = lights["Area"]  # 2 m x 0.5 m, stretched 2x in x, not normalized: power times area
    assert area.size == pytest.approx((4.0, 0.5)) and area.power == pytest.approx(10 * 2.0)
    assert lights["Disk"].size == pytest.approx((2.0, 2.0))
    assert lights["Disk"].power == pytest.approx(4 * 4 * math.pi / 4)
    assert lights["Normalized"].power == pytest.approx(7.0)
    sun = lights["Sun"]
    rotation = np.array(Matrix.Rotation(math.radians(60), 3, "Z") @ Matrix.Rotation(math.radians(30), 3, "X"))
    np.testing.assert_allclose(sun.direction, -rotation[:, 2], atol=1e-6)
    np.testing.assert_allclose(sun.up, rotation[:, 1], atol=1e-6)
    assert sun.power == pytest.approx(3.0)


def test_camera_matrices(mixed):
    camera = mixed["viewport"].camera
    np.testing.assert_allclose(camera.view, mixed["expected_view"], atol=1e-6)
    np.testing.assert_allclose(camera.projection, mixed["expected_projection"], atol=1e-6)
    assert camera.projection[1, 1] / camera.projection[0, 0] == pytest.approx(2.0)  # 200x100 pixels
    square = mixed["square"].camera
    assert square.projection[1, 1] / square.projection[0, 0] == pytest.approx(1.0)
    np.testing.assert_allclose(camera.position, (0, -10, 5), atol=1e-6)


def test_render_resolution_applies_the_percentage():
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 1920, 1080, 50
    assert render_resolution(scene) == (960, 540)


def test_save_and_load_round_trip(mixed, tmp_path):
    scene = mixed["viewport"]
    path = tmp_path / "mixed.npz"
    save_scene(scene, path)
    loaded = load_scene(path)
    assert loaded.geometry_key() == scene.geometry_key()
    assert loaded.camera.key() == scene.camera.key()
    assert [light.key() for light in loaded.lights] == [light.key() for light in scene.lights]
    assert loaded.dropped == scene.dropped


@pytest.fixture(scope="module")
def broken():
    """A good triangle, one with a NaN vertex and two without area (collinear, and two
    corners in one place)."""
    reset_blender()
    nan = float("nan")
    mesh_object("Broken", [(0, 0, 0), (1, 0, 0), (0, 1, 0), (5, 0, 0), (6, 0, 0), (nan, 1, 0),
                           (10, 0, 0), (11, 0, 0), (12, 0, 0), (20, 0, 0), (20, 0, 0), (20, 1, 0)],
                [(0, 1, 2), (3, 4, 5), (6, 7, 8), (9, 10, 11)])
    light_object("Light", "POINT", (0, 0, 3), energy=10)
    return extract_scene(bpy.context.evaluated_depsgraph_get())


def test_broken_triangles_are_dropped_and_counted(broken):
    assert broken.triangle_count == 1
    assert broken.dropped == {"non_finite": 1, "zero_area": 2}
    assert np.all(np.isfinite(broken.triangles)) and np.all(np.isfinite(broken.normals))
    np.testing.assert_allclose(broken.triangles[0], [(0, 0, 0), (1, 0, 0), (0, 1, 0)])


@pytest.mark.parametrize("build, message", [
    (lambda: light_object("Light", "POINT", (0, 0, 3), energy=10), "no renderable triangles"),
    (lambda: unit_quad("Lonely"), "no lights"),
], ids=["without meshes", "without lights"])
def test_an_incomplete_scene_is_a_clear_error(build, message):
    reset_blender()
    build()
    with pytest.raises(LPVError, match=message) as error:
        extract_scene(bpy.context.evaluated_depsgraph_get())
    assert str(error.value).endswith(".")


def test_scene_without_camera_has_no_camera():
    reset_blender()
    unit_quad("Quad")
    light_object("Light", "POINT", (0, 0, 3), energy=10)
    assert extract_scene(bpy.context.evaluated_depsgraph_get()).camera is None


def grid_object(name, quads_per_side):
    """A wavy grid of quads_per_side² quads, built with foreach_set."""
    n = quads_per_side + 1
    u = np.linspace(0.0, 1.0, n)
    x, y = np.meshgrid(u, u, indexing="ij")
    positions = np.stack([x, y, 0.1 * np.sin(6 * x) * np.cos(5 * y)], axis=-1).reshape(-1, 3)
    index = np.arange(n * n).reshape(n, n)
    quads = np.stack([index[:-1, :-1], index[1:, :-1], index[1:, 1:], index[:-1, 1:]], axis=-1).reshape(-1, 4)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.astype(np.float32).ravel())
    mesh.loops.add(quads.size)
    mesh.loops.foreach_set("vertex_index", quads.astype(np.int32).ravel())
    mesh.polygons.add(len(quads))
    mesh.polygons.foreach_set("loop_start", np.arange(0, quads.size, 4, dtype=np.int32))
    mesh.update(calc_edges=True)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def test_a_million_triangles_extract_quickly():
    reset_blender()
    grid_object("Million", 708)  # 708² quads = 1,002,528 triangles
    light_object("Light", "POINT", (0.5, 0.5, 2), energy=10)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    start = time.perf_counter()
    scene = extract_scene(depsgraph)
    seconds = time.perf_counter() - start
    print(f"\nextract_scene: {scene.triangle_count:,} triangles in {seconds:.2f} s")
    assert scene.triangle_count == 2 * 708 ** 2
    assert seconds < 10.0
