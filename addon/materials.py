"""A material's diffuse colour as the renderer takes it: a constant, times an image read
at a UV map, times a colour attribute.

The Cycles output's Surface is followed to a Principled BSDF (whose diffuse part Cycles
scales by 1 - metallic and 1 - transmission) or a Diffuse BSDF; their colour input is
evaluated exactly when it is a constant, an RGB node, an Image Texture (its Vector from
nothing, a UV Map node or Texture Coordinate's UV), a Color Attribute or a geometry
Attribute node, or a Mix of those with a constant factor that multiplies or picks one
side. Anything else is approximated the way the renderer has always done it (the
nearest upstream image's average, or the socket's or the material's display colour), and
the material is named in `approximated`: the panel and stats.json list them. Shaders the
preview does not render as Cycles does (UNSUPPORTED_SHADERS, PRINCIPLED_UNSUPPORTED, a
linked Volume) name what they are and what the preview does with them beside the name.

A surface also lets light through (docs/method.md, "Alpha and transmission"): its
`alpha` (the Principled BSDF's Alpha, a constant or an Image Texture's Alpha output, and
the Transparent BSDF of a Mix Shader) cuts it out, and its transmission (the Principled
BSDF's Transmission Weight, a Glass or Refraction BSDF, a coloured Transparent BSDF) is
seen and lit through, tinted: a thin sheet without refraction. Its glossy reflection
(docs/method.md, "Specular light") is the Principled BSDF's F0, roughness and metallic
share, read as constants.
"""
from dataclasses import dataclass, replace

import numpy as np

from .image_pixels import LINEAR_COLOUR_SPACES, alpha_channel, linear_pixels, tile_pixels

DEFAULT_ALBEDO = (0.8, 0.8, 0.8)
"""Blender's colour for a surface without a material."""

NON_REFLECTING_SHADERS = {"EMISSION", "HOLDOUT", "BSDF_TRANSPARENT"}

TRANSMITTING_SHADERS = {"BSDF_GLASS", "BSDF_REFRACTION", "BSDF_TRANSPARENT"}
"""Shader nodes read as a thin sheet that transmits all light, tinted by their Color."""
"""Shader nodes that reflect no light diffusely."""

AS_DISPLAY_COLOUR = "rendered as an opaque diffuse surface in the display colour"
AS_OPAQUE_BLACK = "rendered as an opaque black surface"
VOLUME = "volume (rendered as an opaque surface)"

AS_THIN_SHEET = "seen and lit through as a thin tinted sheet: no refraction, reflection or caustics"

UNSUPPORTED_SHADERS = {
    "BSDF_GLASS": f"glass ({AS_THIN_SHEET})",
    "BSDF_REFRACTION": f"refraction ({AS_THIN_SHEET})",
    "BSDF_TRANSLUCENT": f"translucency ({AS_DISPLAY_COLOUR})",
    "SUBSURFACE_SCATTERING": f"subsurface scattering ({AS_DISPLAY_COLOUR})",
    "BSDF_HAIR": f"hair ({AS_DISPLAY_COLOUR})",
    "BSDF_HAIR_PRINCIPLED": f"hair ({AS_DISPLAY_COLOUR})",
    "BSDF_TOON": f"toon ({AS_DISPLAY_COLOUR})",
    "BSDF_SHEEN": f"sheen ({AS_DISPLAY_COLOUR})",
    "BSDF_GLOSSY": f"glossy reflection ({AS_DISPLAY_COLOUR})",
    "BSDF_METALLIC": f"metallic reflection ({AS_DISPLAY_COLOUR})",
    "BSDF_RAY_PORTAL": f"ray portal ({AS_DISPLAY_COLOUR})",
    "EEVEE_SPECULAR": f"EEVEE specular ({AS_DISPLAY_COLOUR})",
    "HOLDOUT": f"holdout ({AS_OPAQUE_BLACK}, not cut out)",
    "PRINCIPLED_VOLUME": VOLUME,
    "VOLUME_SCATTER": VOLUME,
    "VOLUME_ABSORPTION": VOLUME,
    "VOLUME_COEFFICIENTS": VOLUME,
}
"""Shader node type -> what it is and what the preview does with it, for the shaders the
preview does not render as Cycles does: one table, so that the list of approximated
materials says the same of every material using one."""

PRINCIPLED_UNSUPPORTED = {
    "Transmission Weight": f"transmission ({AS_THIN_SHEET})",
    "Subsurface Weight": "subsurface scattering (rendered as plain diffuse)",
    "Coat Weight": "coat (folded into the one glossy lobe; its tint and normal left out)",
    "Sheen Weight": "sheen (left out)",
    "Anisotropic": "anisotropy (an isotropic lobe)",
    "Thin Film Thickness": "thin film (left out)",
}
"""Principled BSDF inputs -> what the preview does with them, where they differ from
their no-effect value (0) or are linked."""

ALPHA_APPROXIMATED = "alpha approximated (an input the preview does not evaluate: taken at its own value)"

COLOUR_APPROXIMATED = "diffuse colour approximated"

SPECULAR_INPUTS = ("Roughness", "IOR", "Specular IOR Level", "Specular Tint")
"""The Principled BSDF's inputs its glossy reflection reads (with Metallic and Base
Color): a linked one is taken at its socket's value and the material approximated."""


def principled_specular(base, metallic, ior, level, tint):
    """F0, the Principled BSDF's reflectance at normal incidence, as Cycles makes it: the
    dielectric's ((ior - 1) / (ior + 1))² times 2 x Specular IOR Level, tinted by Specular
    Tint, mixed toward the base colour by Metallic (a metal's edge tint, F82, is not
    modelled)."""
    ior = max(float(ior), 1e-3)
    dielectric = ((ior - 1.0) / (ior + 1.0)) ** 2 * 2.0 * max(float(level), 0.0) * np.asarray(tint, np.float64)[:3]
    f0 = (1.0 - metallic) * np.clip(dielectric, 0.0, 1.0) + metallic * np.asarray(base, np.float64)[:3]
    return tuple(float(c) for c in np.clip(f0, 0.0, 1.0))



def with_coat(specular, roughness, weight, coat_roughness, coat_ior):
    """The one glossy lobe of a Principled BSDF under a coat of `weight`: the coat's
    dielectric F0 at Coat IOR added over the base's F0 (what the coat lets through), the
    lobe's roughness the two lobes' roughnesses weighted by their F0s."""
    base = np.asarray(specular, np.float64)
    ior = max(float(coat_ior), 1e-3)
    coat = float(np.clip(weight, 0.0, 1.0)) * ((ior - 1.0) / (ior + 1.0)) ** 2
    f0 = np.clip(base + coat * (1.0 - base), 0.0, 1.0)
    share = float(base.mean())
    blended = (share * roughness + coat * float(coat_roughness)) / max(share + coat, 1e-9)
    return tuple(float(c) for c in f0), float(np.clip(blended, 0.0, 1.0))


UPSTREAM_IMAGE_SEARCH_DEPTH = 8
"""How many nodes back from a colour socket an Image Texture is still looked for."""

MISSING_PIXELS = np.array([[[1.0, 0.0, 1.0]]], dtype=np.float32)
"""What an image without pixels (a missing file, a missing UDIM tile) shows: magenta, as in
Blender and Cycles."""


@dataclass(frozen=True)
class BaseColour:
    """What a surface's diffuse colour is made of: the linear `factor`, times the `image`
    (a bpy Image, None: none) at the UV map `uv_map` ("": the active render one), times
    the colour attribute `attribute` ("": the active render one; None: none); `material`
    names whose colour it is; `emission` is the radiance it emits (W/(m² sr), linear).

    What of the light meeting the surface is not cut out is `alpha` (times, where
    `alpha_image` is an image, its alpha channel at the UV map `alpha_uv_map`); of that,
    the share `transmission` passes through tinted by `transmission_tint`, and the rest
    is the surface the colour describes (the colour is already scaled by neither).

    Its glossy reflection (docs/method.md, "Specular light") is GGX of `roughness`
    (Blender's, squared in the shader) with the reflectance `specular` at normal
    incidence (F0, linear rgb; black: none, principled_specular), its Fresnel a
    dielectric's by that F0 where `metallic` is 0, Schlick's where it is 1."""

    factor: tuple
    image: object = None
    uv_map: str = ""
    attribute: str = None
    material: str = ""
    emission: tuple = (0.0, 0.0, 0.0)
    alpha: float = 1.0
    alpha_image: object = None
    alpha_uv_map: str = ""
    transmission: float = 0.0
    transmission_tint: tuple = (1.0, 1.0, 1.0)
    specular: tuple = (0.0, 0.0, 0.0)
    roughness: float = 1.0
    metallic: float = 0.0

    @property
    def varies(self):
        return self.image is not None or self.attribute is not None

    @property
    def opaque(self):
        return self.alpha >= 1.0 and self.alpha_image is None and self.transmission <= 0.0

    def scaled(self, scale):
        return replace(self, factor=tuple(float(f) * float(s) for f, s in zip(self.factor, np.broadcast_to(scale, 3))))

    def see_through(self, alpha, transmission, tint):
        """This colour with `alpha`, `transmission` and `transmission_tint` `tint`."""
        return replace(self, alpha=float(alpha), transmission=float(transmission),
                       transmission_tint=tuple(float(c) for c in tint))


def constant(colour):
    return BaseColour(tuple(float(c) for c in colour[:3]))


BLACK = constant((0.0, 0.0, 0.0))


class MaterialSurfaces:
    """The BaseColour of every material slot, cached per material, with the images they
    read (linear pixels, read once each), the images missing and the materials only
    approximated."""

    def __init__(self):
        self._materials = {}
        self._averages = {}
        self.images = {}            # (image pointer, UDIM tile or None) -> (H, W, 3) linear pixels, top row first
        self.missing_images = set()  # names of the images (and "name tile N") without pixels, rendered magenta
        self.approximated = set()   # material names
        self.unsupported = {}       # material name -> what of it the preview does not support, in words

    def palette(self, obj, size):
        """The BaseColour of the object's material slots 0..size-1; indices past the last
        slot use the last slot, as Blender does."""
        slots = [slot.material for slot in obj.material_slots] or [None]
        colours = [self.base_colour(material) for material in slots[:size]]
        return colours + [colours[-1]] * (size - len(colours))

    def base_colour(self, material):
        if material is None:
            return constant(DEFAULT_ALBEDO)
        key = material.as_pointer()
        if key not in self._materials:
            evaluation = _Evaluation(self)
            colour = replace(evaluation.material(material), emission=evaluation.emission(material))
            if evaluation.approximated or evaluation.unsupported:
                self.approximated.add(material.name)
            if evaluation.unsupported:
                self.unsupported[material.name] = list(evaluation.unsupported) + (
                    [COLOUR_APPROXIMATED] if evaluation.approximated else [])
            self._materials[key] = replace(colour, material=material.name)
        return self._materials[key]

    def approximated_entries(self, names):
        """The list that stats.json and the panel show of the approximated materials
        `names`: a name alone when its diffuse colour is approximated, "name: what" when
        it has shaders the preview does not support ("Smoke: volume (rendered as an
        opaque surface)")."""
        return [f"{name}: {'; '.join(self.unsupported[name])}" if name in self.unsupported else name
                for name in sorted(names)]

    def pixels(self, image, tile=None):
        """The image's linear pixels (of a tiled image, those of its tile `tile`; None: its
        first), MISSING_PIXELS where it has none: a missing file is named in
        `missing_images`, a UV outside the tiles there are is not (Cycles shows it
        magenta too)."""
        key = (image.as_pointer(), tile)
        if key not in self.images:
            pixels = linear_pixels(image) if tile is None else tile_pixels(image, tile)
            if pixels is None:
                if tile is None or tile in (t.number for t in image.tiles):
                    self.missing_images.add(image.name if tile is None else f"{image.name} tile {tile}")
                pixels = MISSING_PIXELS
            self.images[key] = pixels
        return self.images[key]

    def rgba(self, image, tile=None):
        """The image's linear pixels with its alpha channel, (H, W, 4) (alpha 1 where it
        has none; a tile's pixels as `pixels` gives them, alpha 1)."""
        key = (image.as_pointer(), tile, "alpha")
        if key not in self.images:
            rgb = self.pixels(image, tile)
            alpha = alpha_channel(image) if tile is None else None
            if alpha is None or alpha.shape != rgb.shape[:2]:
                alpha = np.ones(rgb.shape[:2], np.float32)
            self.images[key] = np.ascontiguousarray(np.dstack([rgb, alpha]), dtype=np.float32)
        return self.images[key]

    def average(self, image):
        """The mean colour of the image (a tiled one's first tile)."""
        key = image.as_pointer()
        if key not in self._averages:
            self._averages[key] = self.pixels(image).reshape(-1, 3).mean(axis=0, dtype=np.float64)
        return self._averages[key]


class _Evaluation:
    """One material's evaluation; notes whether it had to approximate."""

    def __init__(self, surfaces):
        self.surfaces = surfaces
        self.approximated = False
        self.unsupported = {}  # what the preview does not support, in words, in the order met (a dict as a set)

    def material(self, material):
        fallback = constant(material.diffuse_color)
        tree = material.node_tree
        output = tree.get_output_node("CYCLES") if tree is not None else None
        if output is None:
            return fallback
        if linked_node(output.inputs["Volume"]) is not None:
            self.unsupported[VOLUME] = True
        colour = self.shader(output.inputs["Surface"], fallback, depth=0)
        return replace(colour, factor=tuple(float(c) for c in np.clip(colour.factor, 0.0, 1.0)))

    def approximate(self, colour):
        self.approximated = True
        return colour

    def emission(self, material):
        """The radiance the material's Cycles surface emits: an Emission shader's or a
        Principled BSDF's emission colour times strength, summed and weighted through Add
        and Mix shaders (a linked colour or strength is taken at its socket's value and
        the material counted as approximated)."""
        tree = material.node_tree
        output = tree.get_output_node("CYCLES") if tree is not None else None
        if output is None:
            return (0.0, 0.0, 0.0)
        return tuple(float(c) for c in np.maximum(self.emitted(output.inputs["Surface"], 0), 0.0))

    def emitted(self, socket, depth):
        node = linked_node(socket)
        if node is None or depth > 32:
            return np.zeros(3)
        if node.type == "EMISSION":
            return self.value(node.inputs["Color"])[:3] * self.value(node.inputs["Strength"])
        if node.type == "BSDF_PRINCIPLED":
            return self.value(node.inputs["Emission Color"])[:3] * self.value(node.inputs["Emission Strength"])
        if node.type == "ADD_SHADER":
            return self.emitted(node.inputs[0], depth + 1) + self.emitted(node.inputs[1], depth + 1)
        if node.type == "MIX_SHADER":
            first, second = self.emitted(node.inputs[1], depth + 1), self.emitted(node.inputs[2], depth + 1)
            if not (first.any() or second.any()):
                return np.zeros(3)  # nothing emits: the weight does not matter (a cut-out's image alpha)
            weight = self.mix_weight(node)
            return (1.0 - weight) * first + weight * second
        return np.zeros(3)

    def mix_weight(self, node):
        """A Mix Shader's weight of its second shader: its factor, or a half when the
        factor is linked (approximated), for the colour and the emission alike."""
        factor = node.inputs[0]
        if factor.is_linked:
            self.approximated = True
            return 0.5
        return float(np.clip(factor.default_value, 0.0, 1.0))

    def value(self, socket):
        """A socket's own value as an array; a linked one is approximated by it."""
        if socket.is_linked:
            self.approximated = True
        value = socket.default_value
        return np.array(value if np.ndim(value) == 0 else value[:], dtype=np.float64)

    def shader(self, socket, fallback, depth):
        node = linked_node(socket)
        if node is None:
            return BLACK  # An unconnected surface renders black in Cycles.
        if depth > 32:
            return self.approximate(fallback)
        if node.type in TRANSMITTING_SHADERS:  # a thin sheet passing all light, tinted
            if node.type in UNSUPPORTED_SHADERS:
                self.unsupported[UNSUPPORTED_SHADERS[node.type]] = True
            return BLACK.see_through(1.0, 1.0, self.tint(self.colour(node.inputs["Color"], depth)))
        if node.type in UNSUPPORTED_SHADERS:  # named, and rendered as it always was
            self.unsupported[UNSUPPORTED_SHADERS[node.type]] = True
            return BLACK if node.type in NON_REFLECTING_SHADERS else fallback
        if node.type == "BSDF_PRINCIPLED":
            for name, what in PRINCIPLED_UNSUPPORTED.items():
                socket = node.inputs[name]
                if socket.is_linked or float(socket.default_value) != 0.0:
                    self.unsupported[what] = True
            weights = {}
            for name in ("Metallic", "Transmission Weight"):
                weight = node.inputs[name]
                if weight.is_linked:
                    self.approximated = True
                weights[name] = float(np.clip(weight.default_value, 0.0, 1.0))
            dielectric = 1.0 - weights["Metallic"]
            base = self.colour(node.inputs["Base Color"], depth)
            alpha, alpha_image, alpha_uv_map = self.alpha(node.inputs["Alpha"])
            transmission = dielectric * weights["Transmission Weight"]
            colour = base.scaled(dielectric * (1.0 - weights["Transmission Weight"]))
            # Cycles tints each crossing by the square root of the base colour: a closed glass
            # solid, crossed twice, passes the base colour (the preview tints at each surface too)
            tint = np.sqrt(self.tint(base)) if transmission > 0 else (1, 1, 1)
            roughness, ior, level, specular_tint = (self.value(node.inputs[name]) for name in SPECULAR_INPUTS)
            if weights["Metallic"] > 0 and base.varies:
                self.approximated = True  # a textured metal's reflectance: its colour's average
            specular = principled_specular(self.average_of(base), weights["Metallic"], ior, level, specular_tint)
            roughness = float(np.clip(roughness, 0.0, 1.0))
            coat = self.value(node.inputs["Coat Weight"])
            if float(coat) > 0.0:
                specular, roughness = with_coat(specular, roughness, coat, self.value(node.inputs["Coat Roughness"]),
                                                self.value(node.inputs["Coat IOR"]))
            return replace(colour.see_through(alpha, transmission, tint), alpha_image=alpha_image,
                           alpha_uv_map=alpha_uv_map, specular=specular, roughness=roughness,
                           metallic=weights["Metallic"])
        if node.type == "BSDF_DIFFUSE":
            return self.colour(node.inputs["Color"], depth)
        if node.type == "MIX_SHADER":
            first, second = (self.shader(node.inputs[i], fallback, depth + 1) for i in (1, 2))
            image, uv_map = self.alpha_image(node.inputs[0])
            if image is not None and is_clear(first) and second.alpha_image is None:
                # the usual cut-out: Transparent BSDF, the surface, mixed by an image's alpha
                return replace(second, alpha_image=image, alpha_uv_map=uv_map)
            weight = self.mix_weight(node)
            return self.see_through_sum([(1.0 - weight, first), (weight, second)])
        if node.type == "ADD_SHADER":
            return self.see_through_sum([(1.0, self.shader(node.inputs[i], fallback, depth + 1)) for i in (0, 1)])
        if node.type in NON_REFLECTING_SHADERS:
            return BLACK
        return self.approximate(fallback)

    def see_through_sum(self, parts):
        """The weighted sum of shaders' BaseColours: the diffuse colours (combined) and
        what of each is cut out and transmitted, weighted by what of it is not cut out;
        an image's alpha kept when one part alone has it (else taken as 1, approximated)."""
        if all(colour.opaque for _, colour in parts):
            return glossy(self.combined(parts), parts)
        alpha = sum(weight * colour.alpha for weight, colour in parts)
        if alpha <= 0.0:
            return BLACK.see_through(0.0, 0.0, (1, 1, 1))
        colour = self.combined([(weight * colour.alpha, colour) for weight, colour in parts]).scaled(1.0 / alpha)
        transmitted = sum(weight * colour.alpha * colour.transmission for weight, colour in parts)
        tint = (sum(weight * part.alpha * part.transmission * np.array(part.transmission_tint) for weight, part in parts)
                / transmitted if transmitted > 0 else (1, 1, 1))
        images = [part for _, part in parts if part.alpha_image is not None]
        if len(images) > 1:
            self.unsupported[ALPHA_APPROXIMATED] = True
        return replace(glossy(colour.see_through(min(alpha, 1.0), min(transmitted / alpha, 1.0), tint), parts),
                       alpha_image=images[0].alpha_image if len(images) == 1 else None,
                       alpha_uv_map=images[0].alpha_uv_map if len(images) == 1 else "")

    def tint(self, colour):
        """What a BaseColour tints the light passing through a surface once: its mean
        colour (a Glass, Refraction or Transparent BSDF's, at each crossing as Cycles)."""
        return tuple(float(c) for c in np.clip(self.average_of(colour), 0.0, 1.0))

    def alpha(self, socket):
        """(constant, image, UV map) of an alpha input: its value, or 1 times the alpha
        of the Image Texture whose Alpha output feeds it; anything else is taken at the
        socket's own value (approximated)."""
        image, uv_map = self.alpha_image(socket)
        if image is not None:
            return 1.0, image, uv_map
        if socket.is_linked:
            self.unsupported[ALPHA_APPROXIMATED] = True
        return float(np.clip(socket.default_value, 0.0, 1.0)), None, ""

    def alpha_image(self, socket):
        """(image, UV map) of the Image Texture whose Alpha output feeds `socket`, or
        (None, "")."""
        node = linked_node(socket)
        if node is None or node.type != "TEX_IMAGE" or node.image is None or linked_output(socket) != "Alpha":
            return None, ""
        if node.image.source == "TILED":  # a UDIM tile's alpha is not read: taken as opaque
            self.unsupported[ALPHA_APPROXIMATED] = True
            return None, ""
        return node.image, self.image_colour(node).uv_map

    def combined(self, parts):
        """The weighted sum of BaseColours: exact when at most one part varies and the
        others are black or weightless, else their averages summed (approximated)."""
        parts = [(weight, colour) for weight, colour in parts if weight > 0 and any(colour.factor)]
        if not parts:
            return BLACK
        if len(parts) == 1:
            weight, colour = parts[0]
            return colour.scaled(weight)
        if not any(colour.varies for _, colour in parts):
            return constant(sum(weight * np.array(colour.factor) for weight, colour in parts))
        return self.approximate(constant(sum(weight * self.average_of(colour) for weight, colour in parts)))

    def average_of(self, colour):
        """A BaseColour's mean colour: its image's average times its factor."""
        average = np.array(colour.factor, dtype=np.float64)
        if colour.image is not None:
            average = average * self.surfaces.average(colour.image)
        return average

    def colour(self, socket, depth):
        """The BaseColour a colour input reads."""
        node = linked_node(socket)
        if node is None:
            return constant(socket.default_value)
        if depth > 32:
            return self.approximate(constant(socket.default_value))
        if node.type == "RGB":
            return constant(node.outputs[0].default_value)
        if node.type == "TEX_IMAGE" and node.image is not None:
            return self.image_colour(node)
        if node.type == "VERTEX_COLOR":
            return BaseColour((1.0, 1.0, 1.0), attribute=node.layer_name)
        if node.type == "ATTRIBUTE" and node.attribute_type == "GEOMETRY":
            return BaseColour((1.0, 1.0, 1.0), attribute=node.attribute_name)
        if node.type == "MIX" and node.data_type == "RGBA" or node.type == "MIX_RGB":
            mixed = self.mix_colour(node, depth)
            if mixed is not None:
                return mixed
        image = upstream_image(socket)  # what the renderer did before it read images
        self.approximated = True
        if image is not None:
            return constant(self.surfaces.average(image))
        return constant(socket.default_value)

    def image_colour(self, node):
        colour = BaseColour((1.0, 1.0, 1.0), image=node.image)
        colour_space = node.image.colorspace_settings.name.lower()
        if node.extension != "REPEAT" or not (colour_space.startswith("srgb") or
                                               colour_space.startswith(LINEAR_COLOUR_SPACES)):
            self.approximated = True  # clamped or mirrored lookups, other colour spaces: sampled as repeat, sRGB
        vector = linked_node(node.inputs["Vector"])
        if vector is None:
            return colour
        if vector.type == "UVMAP":
            return replace(colour, uv_map=vector.uv_map)
        if vector.type != "TEX_COORD" or linked_output(node.inputs["Vector"]) != "UV":
            self.approximated = True  # a mapping we do not evaluate: the default UV map
        return colour

    def mix_colour(self, node, depth):
        """A Mix (colour) node with a constant factor: MIX of two sides, or MULTIPLY by a
        constant side; None for the rest."""
        if node.type == "MIX":
            factor, a, b = node.inputs["Factor"], node.inputs[6], node.inputs[7]
        else:
            factor, a, b = node.inputs["Fac"], node.inputs["Color1"], node.inputs["Color2"]
        if factor.is_linked:
            return None
        weight = float(np.clip(factor.default_value if np.ndim(factor.default_value) == 0
                               else factor.default_value[0], 0.0, 1.0))
        first, second = self.colour(a, depth + 1), self.colour(b, depth + 1)
        if node.blend_type == "MIX":
            return self.combined([(1.0 - weight, first), (weight, second)])
        if node.blend_type == "MULTIPLY":
            if not second.varies:  # a ((1 - w) + w b): a scaled
                return first.scaled((1.0 - weight) + weight * np.array(second.factor))
            if not first.varies and weight == 1.0:  # a b: b scaled
                return second.scaled(first.factor)
        return None


def glossy(colour, parts):
    """`colour` with the glossy reflection of the weighted shaders `parts` (weight,
    BaseColour): their F0s weighted by what of each is not cut out, per the share not
    cut out of the sum, and their roughnesses weighted by their F0s (a mean roughness:
    two lobes become one), and so their metallic shares."""
    alpha = sum(weight * part.alpha for weight, part in parts)
    if alpha <= 0.0:
        return colour
    specular = sum(weight * part.alpha * np.array(part.specular) for weight, part in parts) / alpha
    shares = [(weight * part.alpha * max(part.specular), part.roughness) for weight, part in parts]
    total = sum(share for share, _ in shares)
    roughness = sum(share * r for share, r in shares) / total if total > 0 else 1.0
    metallic = sum(share * part.metallic for share, (_, part) in zip((s for s, _ in shares), parts))
    return replace(colour, specular=tuple(float(c) for c in np.clip(specular, 0.0, 1.0)), roughness=float(roughness),
                   metallic=float(metallic / total) if total > 0 else 0.0)


def is_clear(colour):
    """Whether a BaseColour lets all light through untouched (a white Transparent BSDF)."""
    return (not any(colour.factor) and colour.alpha_image is None and
            (colour.alpha <= 0.0 or colour.transmission >= 1.0 and min(colour.transmission_tint) >= 1.0))


def linked_node(socket):
    """The node feeding `socket`, looking through reroutes, muted links and muted nodes."""
    link = _live_link(socket)
    return None if link is None else link.from_node


def linked_output(socket):
    """The name of the output socket feeding `socket`, as linked_node finds it."""
    link = _live_link(socket)
    return None if link is None else link.from_socket.name


def _live_link(socket):
    for _ in range(64):
        links = [link for link in socket.links if not link.is_muted]
        if not links:
            return None
        node = links[0].from_node
        if node.type == "REROUTE":
            socket = node.inputs[0]
        elif node.mute:
            passing = [link.from_socket for link in node.internal_links if link.to_socket == links[0].from_socket]
            if not passing:
                return None
            socket = passing[0]
        else:
            return links[0]
    return None


def upstream_image(socket):
    """The image of the nearest Image Texture node upstream of `socket`, if any."""
    frontier = [socket]
    for _ in range(UPSTREAM_IMAGE_SEARCH_DEPTH):
        nodes = [node for node in (linked_node(s) for s in frontier) if node is not None]
        for node in nodes:
            if node.type == "TEX_IMAGE" and node.image is not None:
                return node.image
        frontier = [s for node in nodes for s in node.inputs if s.is_linked]
        if not frontier:
            return None
    return None

