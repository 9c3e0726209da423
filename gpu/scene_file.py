"""The .npz scene file: a Scene saved where Blender builds it and loaded where there is no
Blender (the GPU machine), with the Cycles one-bounce indirect image of its camera stored
beside it (NAME.cycles.npz) for the sweeps' errors against Cycles.
"""
from pathlib import Path

import numpy as np

from .errors import LPVError
from .scene import Camera, Film, Light, Scene, SurfaceImage
from .world import World

SURFACE_FIELDS = ("visibility", "vertex_colors", "uvs", "image_layers", "emission", "point_emitters", "alpha",
                  "alpha_layers", "transmission", "specular", "solids")
"""The Scene's optional arrays (per triangle, and the point emitters), saved when present."""
LIGHT_FIELDS = ("kind", "position", "direction", "up", "color", "power", "radius", "spot_size", "spot_blend", "size",
                "name", "shape", "angle")


def save_scene(scene, path):
    """Write `scene` to an .npz file that `load_scene` reads without Blender."""
    lights = {f"light{i}_{name}": np.asarray(getattr(light, name))
              for i, light in enumerate(scene.lights) for name in LIGHT_FIELDS}
    camera = {} if scene.camera is None else {
        "camera_view": scene.camera.view, "camera_projection": scene.camera.projection}
    surface = {name: getattr(scene, name) for name in SURFACE_FIELDS if getattr(scene, name) is not None}
    images = {f"image{i}_{part}": value for i, image in enumerate(scene.images)
              for part, value in (("name", image.name), ("pixels", image.pixels))}
    world = {} if scene.world is None else {
        "world_lighting": scene.world.lighting, "world_background": scene.world.background,
        "world_approximated": np.array(scene.world.approximated, dtype=str)}
    film = {"film": np.array([scene.film.filter_width, float(scene.film.transparent)])}
    if scene.diffuse_bounces is not None:
        film["diffuse_bounces"] = np.array(scene.diffuse_bounces)
    film["filter_glossy"] = np.array(scene.filter_glossy)
    try:
        np.savez_compressed(path, triangles=scene.triangles, normals=scene.normals, albedo=scene.albedo,
                            light_count=len(scene.lights), **lights, **camera, **surface,
                            image_count=len(scene.images), **images, **world, **film,
                            approximated_materials=np.array(scene.approximated_materials, dtype=str),
                            dropped=np.array([scene.dropped["non_finite"], scene.dropped["zero_area"]]))
    except OSError as error:
        raise LPVError(f"Cannot write scene file '{path}' ({error.strerror}); choose a writable path.")


def _light_softness(data, i):
    """Light `i`'s area shape and sun angle, where the file has them (older files: none)."""
    return {name: cast(data[f"light{i}_{name}"]) for name, cast in (("shape", str), ("angle", float))
            if f"light{i}_{name}" in data}


def load_scene(path):
    """The Scene of an .npz file written by `save_scene`."""
    if not Path(path).is_file():
        raise LPVError(f"There is no scene file '{path}'; make it with `python -m lpv_preview export`.")
    try:
        data = np.load(path)
    except (OSError, ValueError) as error:
        raise LPVError(f"Cannot read scene file '{path}' ({error}); export it again with 'lpv_preview export'.")
    lights = []
    for i in range(int(data["light_count"])):
        get = lambda name: data[f"light{i}_{name}"]
        lights.append(Light(kind=str(get("kind")), position=get("position"), direction=get("direction"),
                            up=get("up"), color=get("color"), power=float(get("power")),
                            radius=float(get("radius")), spot_size=float(get("spot_size")),
                            spot_blend=float(get("spot_blend")), size=tuple(get("size").tolist()),
                            name=str(get("name")), **_light_softness(data, i)))
    camera = Camera(data["camera_view"], data["camera_projection"]) if "camera_view" in data else None
    dropped = data["dropped"]
    images = [SurfaceImage(str(data[f"image{i}_name"]), data[f"image{i}_pixels"])
              for i in range(int(data["image_count"]) if "image_count" in data else 0)]
    world = World(data["world_lighting"], data["world_background"],
                  tuple(str(name) for name in data["world_approximated"])) if "world_lighting" in data else None
    film = Film(float(data["film"][0]), bool(data["film"][1])) if "film" in data else Film()
    return Scene(data["triangles"], data["normals"], data["albedo"], lights, camera,
                 {"non_finite": int(dropped[0]), "zero_area": int(dropped[1])},
                 **{name: data[name] for name in SURFACE_FIELDS if name in data}, images=images,
                 approximated_materials=[str(name) for name in data.get("approximated_materials", [])],
                 world=world, film=film,
                 diffuse_bounces=int(data["diffuse_bounces"]) if "diffuse_bounces" in data else None,
                 filter_glossy=float(data["filter_glossy"]) if "filter_glossy" in data else 0.0)


def cycles_reference_path(scene_path):
    """Where the Cycles reference of an .npz scene file is stored: NAME.cycles.npz."""
    return Path(scene_path).with_suffix(".cycles.npz")


def store_cycles_indirect(scene_path, indirect, samples, full_gi_indirect):
    """Keep Cycles' one-bounce and full-GI indirect images (top row first) beside an .npz
    scene file."""
    np.savez_compressed(cycles_reference_path(scene_path), indirect=np.asarray(indirect, dtype=np.float32),
                        full_gi_indirect=np.asarray(full_gi_indirect, dtype=np.float32), samples=int(samples))


def stored_cycles_indirect(scene_path):
    """(indirect image, samples) stored beside an .npz scene file, or None."""
    path = cycles_reference_path(scene_path)
    if not path.is_file():
        return None
    with np.load(path) as data:
        return data["indirect"], int(data["samples"])
