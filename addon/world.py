"""The scene's world as gpu/world.py radiance maps, its node tree evaluated as Cycles
evaluates it for each direction: Background (and Emission) shaders' colour times
strength, mixed and added; colours from RGB nodes, Environment Textures (equirectangular
and mirror ball) at the direction a Mapping node turns, the Sky Texture's models
(sky_models.py; Hosek / Wilkie by Preetham's), Mix Color and Light Path's Is Camera Ray
(the camera's map and the lighting's differ). Anything else takes its socket's own value
and is named as approximated. A Sky Texture's sun disc lights the scene as a sun light
of its size, colour and irradiance, not through the lighting map."""
import math
from dataclasses import replace

import numpy as np
from mathutils import Euler

from ..gpu.colour import LUMINANCE_WEIGHTS
from ..gpu.scene import Light
from ..gpu.world import World, directions_of, map_coordinates
from .image_pixels import linear_pixels
from .materials import linked_node, linked_output
from .sky_models import PhysicalSky, PreethamSky

PROCEDURAL_SIZE = (64, 128)
"""The maps' size (height, width) of a world without images: smooth enough at this size."""
LIGHTING_SIZE = (64, 128)
"""The lighting map's size: what is drawn from is its power, not its detail."""
BACKGROUND_WIDTH = 2048
"""The camera's map is at most this wide (an image's own width below it)."""
MAGENTA = (1.0, 0.0, 1.0)
"""What Blender shows of a missing image."""


def world_and_lights(scene, lamps):
    """The World of a bpy scene (`world_of`) and the lights it is lit by: its `lamps` with
    its Sky Textures' suns (`with_sky_suns`)."""
    world, suns = world_of(scene)
    return world, with_sky_suns(lamps, suns)


def world_of(scene):
    """The World of a bpy scene (None when it has no world that emits anything) and the
    sun lights its Sky Textures' sun discs make (`sky_suns`)."""
    world = scene.world
    if world is None:
        return None, []
    output = _output_node(world)
    if output is None:
        colour = np.array(world.color, dtype=np.float32)
        return (World.uniform(colour) if np.any(colour > 0) else None), []
    evaluation = WorldEvaluation()
    size = evaluation.map_size(output.inputs["Surface"])
    directions = directions_of(*size)
    background = evaluation.radiance(output.inputs["Surface"], directions, camera=True)
    lighting = evaluation.radiance(output.inputs["Surface"], directions, camera=False)
    sunless, suns = lighting, []
    if evaluation.sun_texels:  # a Sky Texture with its sun disc: the tree again without the discs
        sunless = WorldEvaluation(evaluation.sky_models, sun_discs=False).radiance(output.inputs["Surface"],
                                                                                 directions, camera=False)
        suns = sky_suns(evaluation.sun_texels, lighting - sunless)
    if not np.any(sunless > 0) and not np.any(background > 0) and not suns:
        return None, []
    return World(_downsampled(sunless, LIGHTING_SIZE), background.astype(np.float32),
                 tuple(dict.fromkeys(evaluation.approximated))), suns


def sky_suns(sun_texels, disc_radiance):
    """A sun light for each Sky Texture's sun disc that lights anything: its direction,
    its disc's angle, and the irradiance its texel of `disc_radiance` (the lighting map
    with the discs less the map without them: the disc through the node tree after the
    texture, strength and mixes included) carries over the texel's solid angle. As
    EEVEE does with a world's sun, its light then has a shadow map and a light map of its
    own; the rest of the sky stays in the map."""
    suns = []
    height, width = disc_radiance.shape[:2]
    for name, (row, column, direction, angle) in sun_texels.items():
        irradiance = np.maximum(disc_radiance[row, column], 0.0) * texel_solid_angle(row, height, width)
        power = float(irradiance.max())
        if power <= 0.0:
            continue
        up = np.array([0.0, 0.0, 1.0]) if abs(direction[2]) < 0.999 else np.array([1.0, 0.0, 0.0])
        suns.append(Light("SUN", np.zeros(3), -direction, up - direction * float(up @ direction), irradiance / power,
                          power, name=f"{name} sun", angle=float(angle)))
    return suns


MERGED_SUNS_APART = math.radians(0.1)
"""Suns of no size merge within half of this."""


def with_sky_suns(lamps, suns):
    """The scene's `lamps` and its Sky Textures' `suns`, a sun light merged into a Sun lamp
    that points within half the wider disc's angle of it (an artist's lamp set along the
    sky's sun): one light of their summed irradiance, along their mean direction and of
    their mean angle (weighted by luminance), whose light map and shadows are made once."""
    lamps = list(lamps)
    for sun in suns:
        for index, lamp in enumerate(lamps):
            if lamp.kind != "SUN":
                continue
            apart = math.acos(float(np.clip(lamp.direction @ sun.direction, -1.0, 1.0)))
            if apart <= max(lamp.angle, sun.angle, MERGED_SUNS_APART) / 2:
                lamps[index] = merged_sun(lamp, sun)
                break
        else:
            lamps.append(sun)
    return lamps


def merged_sun(lamp, sun):
    """One sun light of both's irradiance, named as the lamp, along and as wide as their
    luminance-weighted means."""
    irradiance = lamp.color * lamp.power + sun.color * sun.power
    weights = np.array([lamp.color @ LUMINANCE_WEIGHTS * lamp.power, sun.color @ LUMINANCE_WEIGHTS * sun.power])
    weights /= weights.sum()  # a sky's sun is never dark (sky_suns)
    power = float(irradiance.max())
    return replace(lamp, direction=weights[0] * lamp.direction + weights[1] * sun.direction, color=irradiance / power,
                   power=power, angle=float(weights[0] * lamp.angle + weights[1] * sun.angle))


def _output_node(world):
    if world.node_tree is None:
        return None
    outputs = [node for node in world.node_tree.nodes if node.type == "OUTPUT_WORLD"
               and node.target in ("ALL", "CYCLES")]
    active = [node for node in outputs if node.is_active_output]
    return (active or outputs or [None])[0]


def _downsampled(image, size):
    """`image` box-filtered to `size` (height, width) when larger (it divides evenly or
    is sampled at the nearest texels)."""
    height, width = size
    if image.shape[0] <= height:
        return image.astype(np.float32)
    rows = np.linspace(0, image.shape[0], height + 1).astype(int)
    columns = np.linspace(0, image.shape[1], width + 1).astype(int)
    summed = np.add.reduceat(np.add.reduceat(image.astype(np.float64), rows[:-1], axis=0), columns[:-1], axis=1)
    counts = np.diff(rows)[:, None, None] * np.diff(columns)[None, :, None]
    return (summed / counts).astype(np.float32)


class WorldEvaluation:
    """One evaluation of a world's node tree over many directions at once."""

    def __init__(self, sky_models=None, sun_discs=True):
        self.approximated = []
        self.sky_models = {} if sky_models is None else sky_models
        self.sun_discs = sun_discs  # put each Sky Texture's sun disc into its texel
        self.sun_texels = {}  # Sky Texture name -> (row, column, direction, disc angle) on a map's grid

    def map_size(self, socket):
        """The map size the tree needs: its widest Environment Texture's (at most
        BACKGROUND_WIDTH wide), else PROCEDURAL_SIZE."""
        widths = [node.image.size[0] for node in _upstream_nodes(socket)
                  if node.type == "TEX_ENVIRONMENT" and node.image is not None and node.image.size[0] > 0]
        if not widths:
            return PROCEDURAL_SIZE
        width = min(max(widths), BACKGROUND_WIDTH)
        return max(width // 2, 1), width

    def radiance(self, socket, directions, camera):
        """The shader linked to `socket` for rays along `directions` (..., 3): what a
        camera ray sees, or with `camera` false what lights a surface."""
        node = linked_node(socket)
        shape = directions.shape[:-1] + (3,)
        if node is None:
            return np.zeros(shape)
        if node.type in ("BACKGROUND", "EMISSION"):
            return self.colour(node.inputs["Color"], directions, camera) * \
                self.value(node.inputs["Strength"], directions, camera)[..., None]
        if node.type == "ADD_SHADER":
            return self.radiance(node.inputs[0], directions, camera) + self.radiance(node.inputs[1], directions, camera)
        if node.type == "MIX_SHADER":
            fac = np.clip(self.value(node.inputs["Fac"], directions, camera), 0.0, 1.0)[..., None]
            return (1 - fac) * self.radiance(node.inputs[1], directions, camera) + \
                fac * self.radiance(node.inputs[2], directions, camera)
        self.approximated.append(f"{node.bl_label}: black")
        return np.zeros(shape)

    def value(self, socket, directions, camera):
        """A float input for each direction."""
        node = linked_node(socket)
        if node is None:
            return np.full(directions.shape[:-1], float(socket.default_value))
        if node.type == "LIGHT_PATH":
            output = linked_output(socket)
            if output == "Is Camera Ray":
                return np.full(directions.shape[:-1], 1.0 if camera else 0.0)
            self.approximated.append(f"Light Path {output}: 0")
            return np.zeros(directions.shape[:-1])
        if node.type == "VALUE":
            return np.full(directions.shape[:-1], float(node.outputs[0].default_value))
        if node.type == "MATH" and node.operation in ("MULTIPLY", "ADD"):
            a = self.value(node.inputs[0], directions, camera)
            b = self.value(node.inputs[1], directions, camera)
            return a * b if node.operation == "MULTIPLY" else a + b
        colour = self.colour(socket, directions, camera)  # a colour into a float: its luminance-free mean
        return colour.mean(axis=-1)

    def colour(self, socket, directions, camera):
        """A colour input for each direction, (..., 3) linear."""
        node = linked_node(socket)
        shape = directions.shape[:-1] + (3,)
        if node is None:
            value = socket.default_value
            value = [value] * 3 if isinstance(value, float) else list(value)[:3]
            return np.broadcast_to(np.array(value, dtype=np.float64), shape)
        if node.type == "RGB":
            return np.broadcast_to(np.array(node.outputs[0].default_value[:3], dtype=np.float64), shape)
        if node.type == "TEX_ENVIRONMENT":
            return self.environment(node, directions, camera)
        if node.type == "TEX_SKY":
            return self.sky(node, directions, camera)
        if node.type == "MIX" and node.data_type == "RGBA" and node.blend_type in ("MIX", "MULTIPLY", "ADD"):
            fac = np.clip(self.value(node.inputs["Factor"], directions, camera), 0.0, 1.0)[..., None]
            a, b = (self.colour(node.inputs[index], directions, camera) for index in (6, 7))
            blended = {"MIX": b, "MULTIPLY": a * b, "ADD": a + b}[node.blend_type]
            return (1 - fac) * a + fac * blended
        if node.type == "VALUE" or node.type == "MATH":
            return np.repeat(self.value(socket, directions, camera)[..., None], 3, axis=-1)
        self.approximated.append(f"{node.bl_label}: its output's value")
        output = node.outputs[linked_output(socket)] if linked_output(socket) in node.outputs else node.outputs[0]
        value = getattr(output, "default_value", (0.0, 0.0, 0.0))
        value = [value] * 3 if isinstance(value, float) else list(value)[:3]
        return np.broadcast_to(np.array(value, dtype=np.float64), shape)

    def vector(self, socket, directions, camera):
        """The vector a texture reads (`socket`, None for a node without the input): the
        direction, through a Mapping node when one is linked."""
        node = None if socket is None else linked_node(socket)
        if node is None or node.type == "TEX_COORD":
            return directions
        if node.type == "MAPPING":
            inner = self.vector(node.inputs["Vector"], directions, camera)
            return mapped(inner, node)
        self.approximated.append(f"{node.bl_label} vector: the direction")
        return directions

    def environment(self, node, directions, camera):
        if node.image is None:
            return np.broadcast_to(np.array(MAGENTA), directions.shape[:-1] + (3,))
        pixels = linear_pixels(node.image)
        if pixels is None:
            self.approximated.append(f"{node.image.name}: missing, magenta")
            return np.broadcast_to(np.array(MAGENTA), directions.shape[:-1] + (3,))
        vector = self.vector(node.inputs.get("Vector"), directions, camera)
        length = np.linalg.norm(vector, axis=-1, keepdims=True)
        vector = vector / np.maximum(length, 1e-30)
        if node.projection == "MIRROR_BALL":
            u, v = mirror_ball_coordinates(vector)
        else:
            u, v = map_coordinates(vector)
        return _bilinear(pixels, u, v, wrap=node.projection != "MIRROR_BALL")

    def sky(self, node, directions, camera):
        """A Sky Texture's colour: its model (sky_models.py) at the vectors it reads; on a
        map's grid of directions the sun disc, far smaller than a texel, is put into the
        texel holding it with its power (`sun_discs`), and the texel and the disc are
        noted (`sun_texels`)."""
        vector = self.vector(node.inputs.get("Vector"), directions, camera)
        vector = vector / np.maximum(np.linalg.norm(vector, axis=-1, keepdims=True), 1e-30)
        model = self.sky_model(node)
        if isinstance(model, PreethamSky):
            return model.radiance(vector)
        if vector.ndim != 3 or vector.shape[1] != 2 * vector.shape[0]:
            return model.radiance(vector)
        radiance = model.radiance(vector, sun=False)
        row, column = np.unravel_index(np.argmax(vector @ model.sun_direction), vector.shape[:2])
        if not camera and model.angular_diameter > 0:  # a sky with a disc reads no vector: its sun is the model's
            self.sun_texels[node.name] = (row, column, model.sun_direction, model.angular_diameter)
        if self.sun_discs:
            height, width = radiance.shape[:2]
            radiance[row, column] += model.sun_power() / texel_solid_angle(row, height, width)
        return radiance

    def sky_model(self, node):
        """The node's sky model, made once per evaluation (the camera's map and the
        lighting's share it, with the texels either computed)."""
        if node.sky_type in ("PREETHAM", "HOSEK_WILKIE"):
            if node.sky_type == "HOSEK_WILKIE":
                self.approximated.append("Sky Texture Hosek / Wilkie: the Preetham model")
            key = ("PREETHAM", tuple(node.sun_direction), node.turbidity)
            make = lambda: PreethamSky(node.sun_direction, node.turbidity)  # noqa: E731
        else:
            key = (node.sky_type, node.sun_disc, node.sun_size, node.sun_intensity, node.sun_elevation,
                   node.sun_rotation, node.altitude, node.air_density, node.aerosol_density, node.ozone_density)
            make = lambda: PhysicalSky(node.sky_type == "MULTIPLE_SCATTERING", *key[1:])  # noqa: E731
        if key not in self.sky_models:
            self.sky_models[key] = make()
        return self.sky_models[key]


def texel_solid_angle(row, height, width):
    """The solid angle of a texel in row `row` (or rows: an array) of an equirectangular map."""
    return 2 * math.pi / width * (np.cos(math.pi * row / height) - np.cos(math.pi * (np.asarray(row) + 1) / height))


def _upstream_nodes(socket, depth=32):
    found, frontier = [], [socket]
    for _ in range(depth):
        nodes = [node for node in (linked_node(s) for s in frontier) if node is not None]
        found += nodes
        frontier = [s for node in nodes for s in node.inputs if s.is_linked]
        if not frontier:
            break
    return found


def mapped(vector, node):
    """A Mapping node's output for `vector`: scaled, rotated (XYZ Euler) and, for points,
    moved; a Texture mapping does the inverse."""
    location = np.array(node.inputs["Location"].default_value) if "Location" in node.inputs else np.zeros(3)
    rotation = np.array(node.inputs["Rotation"].default_value) if "Rotation" in node.inputs else np.zeros(3)
    scale = np.array(node.inputs["Scale"].default_value) if "Scale" in node.inputs else np.ones(3)
    matrix = np.array(Euler(rotation, "XYZ").to_matrix())
    unscaled = np.where(scale == 0, 1.0, scale)
    if node.vector_type == "TEXTURE":
        return ((vector - location) @ matrix) / unscaled
    if node.vector_type == "NORMAL":
        out = (vector / unscaled) @ matrix.T
        return out / np.maximum(np.linalg.norm(out, axis=-1, keepdims=True), 1e-30)
    out = (vector * scale) @ matrix.T
    return out + location if node.vector_type == "POINT" else out


def mirror_ball_coordinates(directions):
    """(u, v from the top) of a mirror ball image seen along -y, as Cycles maps it."""
    d = np.array(directions, dtype=np.float64)
    d[..., 1] -= 1.0
    div = 2.0 * np.sqrt(np.maximum(-0.5 * d[..., 1], 0.0))
    d = d / np.where(div > 0, div, 1.0)[..., None]
    return 0.5 * (d[..., 0] + 1.0), 1.0 - 0.5 * (d[..., 2] + 1.0)


def _bilinear(pixels, u, v, wrap=True):
    """`pixels` (height, width, 3, top row first) at (u, v from the top), bilinear."""
    height, width = pixels.shape[:2]
    x = u * width - 0.5
    y = np.clip(v * height - 0.5, 0.0, height - 1.0)
    x0, y0 = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    if wrap:
        x0, x1 = x0 % width, (x0 + 1) % width
    else:
        x0, x1 = np.clip(x0, 0, width - 1), np.clip(x0 + 1, 0, width - 1)
    y1 = np.minimum(y0 + 1, height - 1)
    top = pixels[y0, x0] * (1 - fx) + pixels[y0, x1] * fx
    bottom = pixels[y1, x0] * (1 - fx) + pixels[y1, x1] * fx
    return top * (1 - fy) + bottom * fy
