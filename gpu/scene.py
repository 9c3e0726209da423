"""The scene as plain arrays: triangles, normals, albedo, lights and a camera.

Everything the GPU stages need, in world space, with Blender's light units already
turned into radiometric quantities (see `Light`). `addon/extract.py` builds one from a
depsgraph; gpu/scene_file.py saves and loads one (for the GPU machine, which has no
Blender).
"""
import hashlib
import itertools
import math
import weakref
from dataclasses import dataclass, field, replace

import numpy as np

from .errors import LPVError
from .specular_albedo import bounce_colours

LIGHT_KINDS = ("POINT", "SPOT", "AREA", "SUN")
AREA_SHAPES = ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE")

SEEN_BY_CAMERA, SEEN_BY_LIGHTS = 1, 2
"""Bits of a triangle's visibility (Blender's ray visibility "Camera" and "Shadow"): the
camera draws it; the lights' maps hold it (it casts shadows and reflects light)."""
SEEN_BY_ALL = SEEN_BY_CAMERA | SEEN_BY_LIGHTS
_VISIBILITY_ORDER = np.array([0, 0, 2, 1], dtype=np.int8)  # camera only, both, lights only

FAR_FROM_ORIGIN = 8
"""A scene whose centre lies farther from the world origin than this many times its size
(rounded up to a power of two) gets a local origin; a nearer one keeps the world's,
where float32 positions lose nothing that matters."""
LOCAL_ORIGIN_STEPS = 1024
"""A local origin is the bounds' centre rounded to 1/LOCAL_ORIGIN_STEPS of that size: a
georeferenced model 1e6 m out renders like one at the world origin, and a bounds change
below the step moves nothing."""


def local_origin(low, high):
    """The local origin (float64) of a scene whose world bounds are `low`, `high`."""
    low, high = np.asarray(low, dtype=np.float64), np.asarray(high, dtype=np.float64)
    if not (np.all(np.isfinite(low)) and np.all(np.isfinite(high))):
        return np.zeros(3)
    size = 2.0 ** math.ceil(math.log2(max(float(np.max(high - low)), 1e-30)))
    centre = (low + high) / 2
    if np.max(np.abs(centre)) <= FAR_FROM_ORIGIN * size:
        return np.zeros(3)
    step = size / LOCAL_ORIGIN_STEPS
    return np.round(centre / step) * step


@dataclass
class Light:
    """One light in world space.

    `power` is Blender's: watts for point, spot and area lights (exposure applied),
    irradiance in W/m² for a sun. `color` is linear RGB and multiplies the power.
    `direction` is the light's -Z axis (where a spot, area or sun points) and `up` its
    +Y axis. Radiant intensity follows Cycles: a point or spot light sends P/(4π) W/sr
    (a spot cut to its cone with Cycles' smoothstep blend), an area light (P/π)·cosθ.

    What softens its shadows (docs/method.md, "Soft shadows"): a point or spot light's
    `radius`, an area light's `size` (world lengths along +X and +Y) and `shape`
    (AREA_SHAPES), a sun's `angle` (the full angle of its disc, radians).
    """

    kind: str
    position: np.ndarray
    direction: np.ndarray
    up: np.ndarray
    color: np.ndarray
    power: float
    radius: float = 0.0
    spot_size: float = math.pi / 4
    spot_blend: float = 0.15
    size: tuple = (0.0, 0.0)
    name: str = "light"
    shape: str = "SQUARE"
    angle: float = 0.0

    def __post_init__(self):
        if self.kind not in LIGHT_KINDS:
            raise LPVError(f"Light '{self.name}' has type {self.kind!r}; supported types are {', '.join(LIGHT_KINDS)}.")
        for name in ("position", "direction", "up", "color"):
            value = np.asarray(getattr(self, name), dtype=np.float64).reshape(3)
            if not np.all(np.isfinite(value)):
                raise LPVError(f"Light '{self.name}' has a non-finite {name}; fix the light's transform or color.")
            setattr(self, name, value)
        self.direction = self.direction / max(np.linalg.norm(self.direction), 1e-30)
        self.up = self.up / max(np.linalg.norm(self.up), 1e-30)
        self.power = float(self.power)
        if self.shape not in AREA_SHAPES:
            raise LPVError(f"Light '{self.name}' has shape {self.shape!r}; supported shapes are "
                           f"{', '.join(AREA_SHAPES)}.")
        if not math.isfinite(self.power) or self.power < 0:
            raise LPVError(f"Light '{self.name}' has power {self.power}; it must be a finite number of at least 0.")

    @property
    def rgb_power(self):
        """Power (or sun irradiance) per colour channel."""
        return self.color * self.power

    @property
    def peak_intensity(self):
        """Largest radiant intensity per channel in W/sr (irradiance in W/m² for a sun)."""
        if self.kind == "SUN":
            return self.rgb_power
        if self.kind == "AREA":
            return self.rgb_power / math.pi
        return self.rgb_power / (4 * math.pi)

    def key(self):
        """A content key: equal keys mean the light's RSM would be the same."""
        parts = [self.kind, self.power, self.radius, self.spot_size, self.spot_blend, tuple(self.size), self.shape,
                 self.angle]
        parts += [tuple(np.round(v, 9)) for v in (self.position, self.direction, self.up, self.color)]
        return hashlib.sha1(repr(parts).encode()).hexdigest()[:16]


@dataclass
class Camera:
    """A camera: world-to-view and projection matrices (OpenGL conventions), 4x4 each."""

    view: np.ndarray
    projection: np.ndarray

    def __post_init__(self):
        self.view = np.asarray(self.view, dtype=np.float64).reshape(4, 4)
        self.projection = np.asarray(self.projection, dtype=np.float64).reshape(4, 4)
        if not (np.all(np.isfinite(self.view)) and np.all(np.isfinite(self.projection))):
            raise LPVError("The camera has a non-finite transform; fix the camera object.")

    @property
    def position(self):
        return np.linalg.inv(self.view)[:3, 3]

    def pixel_angle(self, height):
        """A pixel's width per unit distance in front of the camera, in an image `height`
        pixels tall (orthographic: its width)."""
        return 2.0 / (abs(float(self.projection[1, 1])) * height)

    def moved_by(self, offset):
        """This camera with the world moved by -offset under it: for positions relative to
        a local origin `offset` (computed in float64)."""
        translation = np.eye(4)
        translation[:3, 3] = offset
        return Camera(self.view @ translation, self.projection)

    @staticmethod
    def look_at(eye, target, up=(0, 0, 1), fov_y=math.radians(40), aspect=1.0, near=0.05, far=100.0):
        """A perspective camera at `eye` looking at `target` (for tests and demos)."""
        eye, target, up = (np.asarray(v, dtype=np.float64) for v in (eye, target, up))
        return Camera(look_at_view(eye, target - eye, up), perspective(fov_y, aspect, near, far))

    def key(self):
        return hashlib.sha1(self.view.tobytes() + self.projection.tobytes()).hexdigest()[:16]

    def jittered(self, offset, size):
        """This camera looking through the point `offset` (x, y) pixels from each pixel's
        centre of an image of `size` (width, height): the projection moved in clip space."""
        if not any(offset):
            return self
        projection = self.projection.copy()
        for axis in range(2):
            projection[axis] += 2.0 * offset[axis] / size[axis] * projection[3]
        return Camera(self.view, projection)


@dataclass(frozen=True)
class Film:
    """How the camera's image is made of the light, as Blender's Film panel says: the
    pixel filter's width (Blackman-Harris, in pixels) the anti-aliasing draws from, and
    whether the world is seen (`transparent`: alpha 0 and no colour where no surface is)."""

    filter_width: float = 1.5
    transparent: bool = False


def look_at_view(eye, forward, up):
    """OpenGL world-to-view matrix of an eye looking along `forward`."""
    forward = np.asarray(forward, dtype=np.float64) / np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = right, true_up, -forward
    view[:3, 3] = -view[:3, :3] @ np.asarray(eye, dtype=np.float64)
    return view


def perspective(fov_y, aspect, near, far):
    """OpenGL perspective projection matrix."""
    f = 1.0 / math.tan(fov_y / 2)
    m = np.zeros((4, 4))
    m[0, 0], m[1, 1] = f / aspect, f
    m[2, 2], m[2, 3] = (far + near) / (near - far), 2 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


@dataclass
class SurfaceImage:
    """An image a material's base colour (or alpha) reads: (H, W, 3) linear float32
    pixels, or (H, W, 4) with the alpha channel a material's alpha reads, top row first,
    sampled with the triangles' UVs (V up, Blender's convention)."""

    name: str
    pixels: np.ndarray
    _key: str = field(default=None, repr=False, compare=False)

    def key(self):
        if self._key is None:
            self._key = hashlib.sha1(np.ascontiguousarray(self.pixels, dtype=np.float32).tobytes()).hexdigest()[:16]
        return self._key

    def mean_colour(self):
        """The image's mean linear colour over what its alpha keeps (all of it without
        alpha): what a surface it covers reflects on the whole."""
        pixels = np.asarray(self.pixels, dtype=np.float64)
        weights = np.clip(pixels[..., 3], 0.0, 1.0) if pixels.shape[-1] == 4 else np.ones(pixels.shape[:2])
        total = weights.sum()
        return (pixels[..., :3] * weights[..., None]).sum(axis=(0, 1)) / total if total > 0 else np.zeros(3)


def triangle_bounds(triangles):
    """(min, max) float64 corners of the box around (T, 3, 3) triangles; an axis at a time
    (numpy's reduction over the first axis of a (3T, 3) array took four times as long)."""
    corners = np.asarray(triangles).reshape(-1, 3)
    if not len(corners):
        return np.zeros(3), np.zeros(3)
    return tuple(np.array([reduce(corners[:, axis]) for axis in range(3)], dtype=np.float64)
                 for reduce in (np.min, np.max))


POINT_EMITTER_COLUMNS = 7  # position xyz, flux rgb, area
_ARRAY_KEYS = {}  # id of an array -> (a weak reference to it, its key)
_NEXT_ARRAY_KEY = itertools.count()


ENCLOSURE_ARRAYS = ("triangles", "visibility", "alpha", "alpha_layers", "solids")
"""A Scene's arrays that Scene.enclosure_key hashes whole (beside which triangles emit and
which transmit); geometry_key hashes its digest and SURFACE_ARRAYS."""
SURFACE_ARRAYS = ("normals", "albedo", "vertex_colors", "uvs", "image_layers", "emission", "transmission", "specular")


def array_key(array):
    """A key of `array` as an object, the same while it lives and never another's: a
    sanitized scene's arrays are not changed in place (make a new array), so a new array
    is a new key and the same array, in any Scene, the same one."""
    held = _ARRAY_KEYS.get(id(array))
    if held is not None and held[0]() is array:
        return held[1]
    identity = id(array)
    key = f"array-{next(_NEXT_ARRAY_KEY)}"
    _ARRAY_KEYS[identity] = (weakref.ref(array, lambda _: _ARRAY_KEYS.pop(identity, None)), key)
    return key


def _point_emitter_rows(emitters):
    """The point emitters as contiguous float32 rows (the rows given, not a copy, when they
    are; None when there are none). Their values are checked on the GPU: a row not finite,
    with a negative flux or area or no flux is dropped there and counted (shaders/
    emitter_select.comp), where checking a million rows here took longer than the frame."""
    if emitters is None:
        return None
    rows = np.asarray(emitters)
    if rows.ndim != 2 or rows.shape[1] != POINT_EMITTER_COLUMNS or not np.issubdtype(rows.dtype, np.number):
        raise LPVError(f"The point emitters are an array of shape {rows.shape}; give one row of "
                       f"{POINT_EMITTER_COLUMNS} numbers per emitter: position xyz, flux rgb, area.")
    return np.ascontiguousarray(rows, dtype=np.float32) if len(rows) else None


@dataclass
class Scene:
    """Triangles in world space, their surfaces, lights and a camera.

    `triangles` is (T, 3, 3) float32 vertex positions, `normals` (T, 3, 3) float32 unit
    vertex normals (flat or smooth as the mesh says), `albedo` (T, 3) float32 linear
    diffuse colour, `visibility` (T,) uint8 bits SEEN_BY_CAMERA and SEEN_BY_LIGHTS (None:
    seen by both). A textured surface's colour is its albedo times, per corner,
    `vertex_colors` (T, 3, 3) linear (None: white) and times the image `images[layer]`
    at the corners' `uvs` (T, 3, 2) where `image_layers` (T,) is not -1 (None: no image).
    `emission` (T, 3) float32 is the radiance each triangle emits from both sides (None:
    none). `point_emitters` (M, 7) float32 are emitters too small to be surfaces
    (emissive particles and instances): position xyz, flux rgb (W, sent alike in every
    direction) and the area of the surface it comes from (m²: the camera sees a sphere of
    that surface, and 1/r² next to it is bounded as a disc of that area bounds it; None:
    none). What of each triangle lets light through (docs/method.md, "Alpha and
    transmission"): `alpha` (T,) float32, the share of the light meeting it that is not
    cut out, times the alpha channel of the image `images[layer]` at its `uvs` where
    `alpha_layers` (T,) is not -1 (None: 1, no image); `transmission` (T, 4) float32, of
    what is not cut out the share (w) that passes through tinted by the linear colour
    (rgb) (None: none). `albedo` is the mean of the whole surface not cut out; the part
    that does not transmit has albedo / (1 - transmission). `specular` (T, 4) float32
    is each triangle's glossy reflection (docs/method.md, "Specular light"): the
    reflectance at normal incidence F0 (rgb, linear), Blender's roughness and the
    metallic share (its Fresnel: a dielectric's at 0, Schlick's at 1) (None: none, a
    purely diffuse scene; (T, 4) without the metallic share: 0). `solids` (T,) int32
    names the closed mesh (watertight, consistently wound: addon/extract.py) each triangle
    is a face of, one number per placed instance, -1 for an open mesh's triangle (None:
    none is closed); gpu/closed_meshes.py tells from it which side of a face light can
    reach. `world` (gpu/world.py World; None: none) lights the scene from afar and is
    what the camera sees where it sees no surface; `film` (Film) says how the pixels are
    filtered and whether that world is seen; `diffuse_bounces` is how often diffuse light
    may bounce, as its Light Paths say (Cycles' Diffuse bounces within Max Bounces; None:
    the scene says nothing), and `filter_glossy` how much they blur a glossy layer reached
    after a diffuse bounce (Cycles' Filter Glossy; 0: not at all, gpu/vpl.py glossy_blur_alpha).
    `approximated_materials` names the materials the extraction could only approximate:
    a name alone when their colour is approximated, "name: what" for shaders the preview
    does not support ("Smoke: volume (rendered as an opaque surface)"); `missing_images`
    names the images without pixels (missing files), which `images` holds as magenta.
    Positions, lights and camera are relative to the world point `origin`
    (float64; None: the world origin), which `sanitize` moves to the scene when it is far
    (`local_origin`) before anything becomes float32. `dropped` counts what `sanitize` removed, by reason. Once sanitized, the
    triangles the camera sees are the range `camera_triangles` (first, count) and those
    the lights see `light_triangles`: the camera-only ones come first, then those both
    see, then the lights-only ones.
    """

    triangles: np.ndarray
    normals: np.ndarray
    albedo: np.ndarray
    lights: list
    camera: Camera = None
    dropped: dict = field(default_factory=lambda: {"non_finite": 0, "zero_area": 0})
    visibility: np.ndarray = None
    vertex_colors: np.ndarray = None
    uvs: np.ndarray = None
    image_layers: np.ndarray = None
    emission: np.ndarray = None
    alpha: np.ndarray = None
    alpha_layers: np.ndarray = None
    transmission: np.ndarray = None
    specular: np.ndarray = None
    solids: np.ndarray = None
    point_emitters: np.ndarray = None
    world: object = None
    film: Film = Film()
    diffuse_bounces: int = None
    filter_glossy: float = 0.0
    images: list = field(default_factory=list)
    approximated_materials: list = field(default_factory=list)
    missing_images: list = field(default_factory=list)
    origin: np.ndarray = None
    sanitized: bool = False
    camera_triangles: tuple = None
    light_triangles: tuple = None
    _bounds: tuple = field(default=None, repr=False, compare=False)
    _content_keys: tuple = field(default=None, repr=False, compare=False)  # geometry_key's, enclosure_key's

    @property
    def triangle_count(self):
        return int(self.triangles.shape[0])

    def surface_colours(self, first=0, count=None):
        """The colour triangles first .. first + count bounce light with: each one's albedo
        times its corners' mean vertex colour and its image's mean colour (the light a
        surface bounces on the whole, where a texture varies within a triangle), under its
        glossy layer, which darkens it and sends on light of its own (gpu/specular_albedo.py)."""
        chosen = slice(first, None if count is None else first + count)
        colours = np.asarray(self.albedo[chosen], dtype=np.float64)
        if self.vertex_colors is not None:
            colours = colours * self.vertex_colors[chosen].mean(axis=1)
        if self.image_layers is not None and self.images:
            layers = np.asarray(self.image_layers[chosen])
            textured = layers >= 0
            means = np.array([image.mean_colour() for image in self.images])
            colours = colours.copy()
            colours[textured] *= means[layers[textured]]
        if self.specular is not None:
            specular = np.asarray(self.specular[chosen], dtype=np.float64)
            metallic = specular[:, 4] if specular.shape[1] > 4 else np.zeros(len(specular))
            colours = bounce_colours(colours, specular[:, :3], metallic, specular[:, 3])
        return colours.astype(np.float32)

    def bounds(self):
        """(min, max) corners of the triangles' bounding box (kept once sanitized)."""
        if self.sanitized and self._bounds is not None:
            return self._bounds
        self._bounds = triangle_bounds(self.triangles)
        return self._bounds

    @property
    def world_origin(self):
        """Where the scene's positions are relative to, in world space (float64)."""
        return np.zeros(3) if self.origin is None else np.asarray(self.origin, dtype=np.float64)

    def in_local_frame(self, lights=None, camera=None, world=False):
        """This scene with world-space `lights` and `camera` (those given) placed relative
        to its origin, and with `world` (a World or None; False: the one it has)."""
        origin = self.world_origin
        changes = {} if world is False else {"world": world}
        if lights is not None:
            changes["lights"] = [replace(light, position=light.position - origin) for light in lights]
        if camera is not None:
            changes["camera"] = camera.moved_by(origin)
        return replace(self, **changes)

    def world_lights(self):
        """The lights in world space."""
        return [replace(light, position=light.position + self.world_origin) for light in self.lights]

    def _rebase(self, triangles):
        """Move the origin to the finite `triangles`' local_origin ((T, 3, 3), any float
        type), lights and camera along; returns the triangles relative to it (float64
        when they moved)."""
        finite = np.isfinite(triangles).all(axis=(1, 2))
        if not finite.any():
            return triangles
        kept = triangles[finite] if not finite.all() else triangles
        shift = local_origin(kept.min(axis=(0, 1)), kept.max(axis=(0, 1)))
        if not np.any(shift):
            return triangles
        self.origin = self.world_origin + shift
        self.lights = [replace(light, position=light.position - shift) for light in self.lights]
        self.camera = None if self.camera is None else self.camera.moved_by(shift)
        if self.point_emitters is not None and np.ndim(self.point_emitters) == 2 and \
                np.shape(self.point_emitters)[1] == POINT_EMITTER_COLUMNS:
            emitters = np.array(self.point_emitters, dtype=np.float64)
            emitters[:, :3] -= shift
            self.point_emitters = emitters
        return np.asarray(triangles, dtype=np.float64) - shift

    def _surface_arrays(self, count):
        """The optional per-triangle arrays, checked and in their GPU types (None: absent)."""
        arrays = {}
        if self.vertex_colors is not None:
            colors = np.asarray(self.vertex_colors, dtype=np.float32).reshape(count, 3, 3)
            arrays["vertex_colors"] = np.clip(np.nan_to_num(colors, nan=1.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
        if self.image_layers is not None:
            layers = np.asarray(self.image_layers, dtype=np.int16).reshape(count)
            layers = np.where((layers >= 0) & (layers < len(self.images)), layers, -1).astype(np.int16)
            uvs = np.zeros((count, 3, 2), np.float32) if self.uvs is None else np.asarray(self.uvs, np.float32)
            arrays["image_layers"] = layers
            arrays["uvs"] = np.nan_to_num(uvs.reshape(count, 3, 2), nan=0.0, posinf=0.0, neginf=0.0)
        if self.emission is not None:
            emission = np.asarray(self.emission, dtype=np.float32).reshape(count, 3)
            arrays["emission"] = np.maximum(np.nan_to_num(emission, nan=0.0, posinf=0.0, neginf=0.0), 0.0)
        if self.alpha is not None:
            alpha = np.asarray(self.alpha, dtype=np.float32).reshape(count)
            arrays["alpha"] = np.clip(np.nan_to_num(alpha, nan=1.0), 0.0, 1.0)
        if self.alpha_layers is not None:
            layers = np.asarray(self.alpha_layers, dtype=np.int16).reshape(count)
            arrays["alpha_layers"] = np.where((layers >= 0) & (layers < len(self.images)), layers, -1).astype(np.int16)
            if "uvs" not in arrays:
                uvs = np.zeros((count, 3, 2), np.float32) if self.uvs is None else np.asarray(self.uvs, np.float32)
                arrays["uvs"] = np.nan_to_num(uvs.reshape(count, 3, 2), nan=0.0, posinf=0.0, neginf=0.0)
        if self.transmission is not None:
            transmission = np.asarray(self.transmission, dtype=np.float32).reshape(count, 4)
            arrays["transmission"] = np.clip(np.nan_to_num(transmission, nan=0.0), 0.0, 1.0)
        if self.specular is not None:
            specular = np.asarray(self.specular, dtype=np.float32).reshape(count, -1)
            if specular.shape[1] == 4:
                specular = np.concatenate([specular, np.zeros((count, 1), np.float32)], axis=1)
            arrays["specular"] = np.clip(np.nan_to_num(specular[:, :5], nan=0.0), 0.0, 1.0)
        if self.solids is not None:
            arrays["solids"] = np.asarray(self.solids, dtype=np.int32).reshape(count)
        return arrays

    @staticmethod
    def _clear(arrays, count):
        """Which triangles let all light through untouched (alpha 0, or all transmitted
        untinted): they are dropped, from every pass."""
        clear = np.zeros(count, dtype=bool)
        if "alpha" in arrays:
            clear |= arrays["alpha"] <= 0.0
        if "transmission" in arrays:
            transmission = arrays["transmission"]
            clear |= (transmission[:, 3] >= 1.0) & (transmission[:, :3].min(axis=1) >= 1.0)
        return clear

    def sanitize(self):
        """Drop triangles the GPU must never see (NaN/inf or zero area), counting them.

        Raises LPVError for a scene with nothing left to render or no light.
        """
        tri = self._rebase(np.asarray(self.triangles).reshape(-1, 3, 3)).astype(np.float32, copy=False)
        nrm = np.asarray(self.normals, dtype=np.float32).reshape(-1, 3, 3)
        alb = np.asarray(self.albedo, dtype=np.float32).reshape(-1, 3)
        seen = (np.full(len(tri), SEEN_BY_ALL, dtype=np.uint8) if self.visibility is None
                else np.asarray(self.visibility, dtype=np.uint8).reshape(-1) & SEEN_BY_ALL)
        surface = self._surface_arrays(len(tri))
        finite = np.isfinite(tri).all(axis=(1, 2)) & np.isfinite(alb).all(axis=1)
        with np.errstate(invalid="ignore", over="ignore"):
            cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
            doubled_area_squared = np.einsum("ij,ij->i", cross, cross).astype(np.float64)
            extent = np.abs(tri).max(axis=(1, 2)).astype(np.float64)
            # An area below float32 resolution at the triangle's own scale is no area.
            has_area = doubled_area_squared > (extent ** 4 + 1e-60) * 1e-24
        clear = self._clear(surface, len(tri))
        keep = finite & has_area & (seen != 0) & ~clear
        self.dropped = {
            "non_finite": self.dropped.get("non_finite", 0) + int((~finite).sum()),
            "zero_area": self.dropped.get("zero_area", 0) + int((finite & ~has_area).sum()),
            **({"clear": self.dropped.get("clear", 0) + int((finite & has_area & clear).sum())}
               if clear.any() or "clear" in self.dropped else {}),
        }
        if "solids" in surface:  # a closed mesh that loses a face has a hole: it is open
            holed = np.unique(surface["solids"][clear | ~finite])
            surface["solids"] = np.where(np.isin(surface["solids"], holed[holed >= 0]), -1, surface["solids"])
        per_triangle = {"tri": tri, "nrm": nrm, "alb": alb, "cross": cross, "seen": seen, **surface}
        if not keep.all():
            per_triangle = {name: array[keep] for name, array in per_triangle.items()}
        if np.any(per_triangle["seen"] != SEEN_BY_ALL):
            order = np.argsort(_VISIBILITY_ORDER[per_triangle["seen"]], kind="stable")
            per_triangle = {name: array[order] for name, array in per_triangle.items()}
        tri, nrm, alb, cross, seen = (per_triangle.pop(name) for name in ("tri", "nrm", "alb", "cross", "seen"))
        # Vertex normals that are missing or broken fall back to the face normal.
        with np.errstate(invalid="ignore", over="ignore"):
            length = np.sqrt(np.einsum("ijk,ijk->ij", nrm, nrm))[..., None]
        bad = ~(length > 1e-6) | ~np.isfinite(length)
        nrm = nrm / np.where(bad, 1.0, length)
        if bad.any():
            face = cross / np.linalg.norm(cross, axis=1, keepdims=True)
            nrm = np.where(bad, face[:, None, :], nrm)
        self._bounds = self._content_keys = None
        self.triangles = np.ascontiguousarray(tri)
        self.normals = np.ascontiguousarray(nrm, dtype=np.float32)
        self.albedo = np.ascontiguousarray(np.clip(alb, 0.0, 1.0))
        self.visibility = None if np.all(seen == SEEN_BY_ALL) else seen
        for name in ("vertex_colors", "uvs", "image_layers", "emission", "alpha", "alpha_layers", "transmission",
                     "specular", "solids"):
            setattr(self, name, np.ascontiguousarray(per_triangle[name]) if name in per_triangle else None)
        if self.emission is not None and not self.emission.any():
            self.emission = None
        if self.alpha is not None and np.all(self.alpha >= 1.0):
            self.alpha = None
        if self.alpha_layers is not None and not np.any(self.alpha_layers >= 0):
            self.alpha_layers = None
        if self.transmission is not None and not np.any(self.transmission[:, 3] > 0.0):
            self.transmission = None
        if self.specular is not None and not np.any(self.specular[:, :3] > 0.0):
            self.specular = None
        if self.image_layers is not None and not np.any(self.image_layers >= 0):
            self.image_layers = None
        if self.solids is not None and not np.any(self.solids >= 0):
            self.solids = None
        if self.image_layers is None and self.alpha_layers is None:
            self.uvs = None
        self.point_emitters = _point_emitter_rows(self.point_emitters)
        camera_only, both = int(np.sum(seen == SEEN_BY_CAMERA)), int(np.sum(seen == SEEN_BY_ALL))
        self.camera_triangles = (0, camera_only + both)
        self.light_triangles = (camera_only, len(seen) - camera_only)
        if self.triangle_count == 0:
            raise LPVError("The scene has no renderable triangles; add a visible mesh object.")
        self.require_lights()
        self.sanitized = True
        return self

    def require_lights(self, point_emitters_lit=True):
        """Refuse a scene that nothing lights; `point_emitters_lit` False: its point emitters
        were all dropped for their values (shaders/emitter_select.comp)."""
        if not self.lights and (self.emission is None or not np.any(self.emission)) and \
                (self.point_emitter_count == 0 or not point_emitters_lit) and \
                (self.world is None or not self.world.lights_anything):
            raise LPVError("The scene has no lights; add a point, spot, area or sun light, an emissive material, or a "
                           "world that emits light.")

    @property
    def point_emitter_count(self):
        return 0 if self.point_emitters is None else len(self.point_emitters)

    @property
    def see_through(self):
        """Whether any triangle is cut out or transmits (the raster passes test alpha)."""
        return self.alpha is not None or self.alpha_layers is not None or self.transmission is not None

    @property
    def hashed(self):
        """Whether some triangle's cut-out is hashed (a share between 0 and 1, or an
        image's alpha): its maps differ from one VPL pattern to the next."""
        coverage = np.ones(self.triangle_count, np.float32) if self.alpha is None else self.alpha.copy()
        if self.transmission is not None:
            coverage *= 1.0 - self.transmission[:, 3]
        return self.alpha_layers is not None or bool(np.any((coverage > 0.0) & (coverage < 1.0)))

    def point_emitters_key(self):
        """A key of the point emitters ("" for none): the array's own, as an object
        (`array_key`), not of its content. Particles move every frame; hashing a million
        rows took longer than the GPU's whole emitter frame."""
        return "" if self.point_emitters is None else array_key(self.point_emitters)

    def geometry_key(self):
        """A content key of the triangles and their surfaces: normals, albedo, visibility,
        vertex colours, UVs and images (kept once sanitized: a sanitized scene's arrays
        are not to be changed in place; make a new Scene)."""
        return self._keys()[0]

    def enclosure_key(self):
        """A content key of what tells solids and rooms apart (gpu/closed_meshes.py): the
        triangles, which cast shadows, which let light through (alpha, and whether each
        transmits), which emit (not how much) and which meshes are closed. A material edit
        of colours or strengths keeps it: sorting a large scene's faces into rooms took
        longer than the rest of the edit."""
        return self._keys()[1]

    def _keys(self):
        """geometry_key and enclosure_key, hashed in one pass over the arrays."""
        if self.sanitized and self._content_keys is not None:
            return self._content_keys
        enclosure, geometry = hashlib.sha1(), hashlib.sha1()
        emits = None if self.emission is None else np.max(self.emission, axis=1) > 0
        transmits = None if self.transmission is None else self.transmission[:, 3] > 0
        for hashed, arrays in ((enclosure, [getattr(self, name) for name in ENCLOSURE_ARRAYS] + [emits, transmits]),
                               (geometry, [getattr(self, name) for name in SURFACE_ARRAYS])):
            for array in arrays:
                hashed.update(b"-" if array is None else memoryview(np.ascontiguousarray(array)).cast("B"))  # no copy
        geometry.update(enclosure.digest())
        for image in self.images:
            geometry.update(image.key().encode())
        self._content_keys = (geometry.hexdigest()[:16], enclosure.hexdigest()[:16])
        return self._content_keys
