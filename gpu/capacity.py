"""Whether a frame fits the machine, checked before anything of it is allocated: its
images against the OpenGL driver's size limits, and the memory it needs against what the
system has free.

The GPU's free memory has no portable OpenGL query, so on a GPU driver only the host
memory of the images read back is compared; llvmpipe keeps its textures in host memory,
so there the GPU bytes count against it too.
"""
import os

from .bounces import light_bounces
from .emitter_bounce import RECEIVER_BYTES, RECEIVER_TRIANGLE_BYTES
from .emitter_grid import CLUSTER_FLOATS, GRID_TEXEL_BYTES, grid_resolution, largest_texture_side
from .errors import LPVError
from .grids import VIEW_LATTICE
from .indirect import indirect_method
from .light_grid import LIGHT_GRID_BYTES_PER_CELL, cluster_bytes
from .occupancy import LARGE_TRIANGLE_BYTES, VOXELS_PER_CELL, occupancy_bytes
from .passes import DEBUG_PASS_NAMES, PASS_NAMES
from .light_maps import SUN_CASCADES
from .mesh_buffer import POSITION_BYTES, STAGED_FLOATS_PER_TRIANGLE, VERTEX_FLOATS
from .rsm import face_atlas_size, map_face_count
from .scene import POINT_EMITTER_COLUMNS
from .shade import DISPLAY_CHANNELS
from .surface_images import BYTES_PER_TEXEL, layer_size
from .vpl import EMITTER_BYTES
from .vpl_gather import pixel_gather_bytes
from .world_light import world_lights

GIB = 2 ** 30

CAMERA_BYTES_PER_PIXEL = 4 * 16 + 16 + 8 + 4 + 4
"""Direct, its mean over the sets, indirect and combined (RGBA32F), the G-buffer's packed
texel (RGBA32UI), its glossy texel (RGBA16UI: F0, roughness and metallic), depth and the
triangle seen (R32UI)."""
IMAGE_COLOUR_BYTES_PER_PIXEL = 8  # the colour of the images seen (RGBA16F), in a scene with images
SEEN_POINTS_BYTES = VIEW_LATTICE ** 2 * 16  # gpu/shade.py seen_points' buffer
DEBUG_BYTES_PER_PIXEL = 2 * 16        # VPL Splats and Warp Status (RGBA32F)
REFLECTION_BYTES_PER_PIXEL = 16       # the Reflections image of a scene with glossy surfaces (RGBA32F)
WORLD_MAP_BYTES_PER_TEXEL = 12        # the world's maps (RGB32F); its lighting map's mip chain adds a third
DISPLAY_BYTES_PER_PIXEL = 4 * DISPLAY_CHANNELS  # the viewport's float rows
READBACK_BYTES_PER_PIXEL = 16         # a pass as the GPU gives it back (RGBA32F), before its RGB copy
PASS_BYTES_PER_PIXEL = 5 * 3 * 4
"""A pass read back (RGB float32) and about four copies more as the caller writes it (an
EXR's interleaved channels, PNG tone mapping, Blender's RenderResult rows): `demo` at
4096 x 4096 peaked at 262 bytes a pixel in all on llvmpipe, this estimate's 264."""

MAP_BYTES_PER_TEXEL = 3 * 16          # an RSM's position, normal and flux (RGBA32F)
TINT_BYTES_PER_TEXEL = 8              # its tint (RGBA16F), in a scene with transmitting surfaces
WARP_STATUS_BYTES_PER_TEXEL = 4
SHARED_BYTES_PER_TEXEL = 4 + 4
"""Per atlas layout: the depth renderbuffer its maps are drawn with and the VPLs' Poisson
cell ids; the warped methods keep a spare set of maps there too (the warp's source)."""
VPL_CELL_BYTES = 16 + 8               # per atlas layout: a Poisson cell's bounds and sample point

VERTEX_BYTES = VERTEX_FLOATS * 4      # position, normal, albedo, surface coordinate, transmission, specular
                                      # (mesh_buffer.py)
RIM_LIST_BYTES_PER_TRIANGLE = 2 * 3 * 4
"""Per paraboloid hemisphere: room for two lists of vertex indices (uint32) of the
triangles split at its rim."""

WARPED_METHODS = ("wdpm", "twdpm", "auto")


def map_method(method):
    """The map layout a method renders: cube faces for "cm", paraboloid hemispheres for the
    others. `auto` chooses the cube only where it has as many faces as the paraboloid (one:
    a sun, a spot of up to 45 degrees), so its layout is the paraboloid's."""
    return "cm" if method == "cm" else "dpm"


def mapped_lights(s, scene):
    """The lights that may get maps: all but the point lights beyond the light-map budget
    (gpu/pipeline.py frame_lights; skipping may leave fewer)."""
    points = [light for light in scene.lights if light.kind == "POINT"]
    return [light for light in scene.lights if light.kind != "POINT"] + points[:s.light_map_budget]


def emitter_bytes(s, scene, pixels, lamps):
    """The emitter grid (gpu/emitter_grid.py: clusters of every level, three textures
    and, super-sampled, three twice as fine, the emitters twice, an irradiance image),
    the emitters' shadows (a light grid with unshadowed volumes, its occupancy and
    clusters), the scene's emitters' glow (gpu/shade.py glow_points: four floats a pixel,
    a list entry an emitter) and the receivers of their bounce, for the scene's point
    emitters and `lamps` point lights beyond the budget."""
    count = scene.point_emitter_count + lamps
    bounce = s.emitter_bounce_samples * RECEIVER_BYTES if count or scene.emission is not None else 0
    if not count:
        return bounce
    side = grid_resolution(s.emitter_grid_resolution)
    fine = 8 * 3 * GRID_TEXEL_BYTES if s.emitter_interpolation == "supersampled" else 0
    grid = (side ** 3 * (CLUSTER_FLOATS * 4 * 8 // 7 + 3 * GRID_TEXEL_BYTES + fine)
            + count * (EMITTER_BYTES + POINT_EMITTER_COLUMNS * 4))
    n = s.lpv_resolution
    shadows = (2 * s.grid_levels * s.grid_phases * n ** 3 * LIGHT_GRID_BYTES_PER_CELL
               + occupancy_bytes(s.grid_levels * s.grid_phases, n, VOXELS_PER_CELL)
               + scene.triangle_count * LARGE_TRIANGLE_BYTES + cluster_bytes(count, s)) \
        if s.emitter_shadows else 0
    glow = pixels * 16 + scene.point_emitter_count * 4 if scene.point_emitter_count else 0
    return grid + shadows + pixels * 16 + glow + bounce


def frame_bytes(settings, scene, passes=PASS_NAMES, display=False):
    """(GPU bytes, host bytes) that a frame of `scene` with `settings` needs at its peak:
    the camera's images (with `display`, the viewport's rows too), every light's maps and
    VPLs, the LPV, the mesh and its images on the GPU; the `passes` read back on the host."""
    s = settings
    pixels = s.width * s.height
    warped = s.method in WARPED_METHODS
    camera = pixels * (CAMERA_BYTES_PER_PIXEL + DISPLAY_BYTES_PER_PIXEL * display
                       + IMAGE_COLOUR_BYTES_PER_PIXEL * bool(scene.images)
                       + DEBUG_BYTES_PER_PIXEL * any(name in DEBUG_PASS_NAMES for name in passes))
    mapped = mapped_lights(s, scene)
    atlases = [face_atlas_size(map_face_count(light, map_method(s.method)), s.rsm_resolution) for light in mapped]
    map_texel = MAP_BYTES_PER_TEXEL + TINT_BYTES_PER_TEXEL * (scene.transmission is not None)
    per_light = map_texel + WARP_STATUS_BYTES_PER_TEXEL * warped
    maps = sum(width * height * per_light + s.vpls_per_light * EMITTER_BYTES for width, height in atlases)
    per_layout = SHARED_BYTES_PER_TEXEL + MAP_BYTES_PER_TEXEL * warped
    maps += sum(width * height * per_layout + s.vpls_per_light * VPL_CELL_BYTES for width, height in set(atlases))
    suns = sum(light.kind == "SUN" for light in mapped)  # each sun's maps fitted to the view (light_maps.py)
    maps += suns * SUN_CASCADES * s.sun_cascade_resolution ** 2 * map_texel
    indirect = indirect_method(s).needed_bytes(s, scene, pixels, len(mapped))
    indirect += emitter_bytes(s, scene, pixels, len(scene.lights) - len(mapped))
    lit_by_world = world_lights(scene, s)
    method = indirect_method(s)
    later_bounces = method.more_bounces and light_bounces(s, scene) > 1
    bouncing = scene.point_emitter_count or scene.emission is not None or lit_by_world or len(scene.lights) > len(mapped)
    if not method.gathers_per_pixel and (bouncing or later_bounces):
        indirect += pixel_gather_bytes(s, scene, pixels)  # the method's pixel gather: the emitters' light, bounces
    if bouncing or later_bounces:  # the surfaces the bounces' points are drawn on
        indirect += scene.triangle_count * RECEIVER_TRIANGLE_BYTES
    if scene.emission is not None:  # emitters, the glow and the triangles' radiances
        indirect += 2 * s.emission_samples * EMITTER_BYTES
        indirect += pixels * 16 + scene.triangle_count * 16
    if scene.world is not None:  # its background and lighting maps, its emitters
        world = scene.world
        indirect += (world.background.size + world.lighting.size * 4 // 3) // 3 * WORLD_MAP_BYTES_PER_TEXEL
        if lit_by_world:
            indirect += s.world_samples * EMITTER_BYTES
    if scene.specular is not None:
        camera += pixels * REFLECTION_BYTES_PER_PIXEL
    rims = 2 * RIM_LIST_BYTES_PER_TRIANGLE * (s.method != "cm")
    # the arrays staged for the interleave are let go before the rim lists are made
    mesh = scene.triangle_count * (3 * (VERTEX_BYTES + POSITION_BYTES) + max(4 * STAGED_FLOATS_PER_TRIANGLE, rims))
    mesh += len(scene.images) * layer_size(scene.images) ** 2 * BYTES_PER_TEXEL
    host = pixels * (READBACK_BYTES_PER_PIXEL * bool(passes) + PASS_BYTES_PER_PIXEL * len(passes))
    return camera + SEEN_POINTS_BYTES + maps + indirect + mesh, host


def available_host_bytes():
    """Memory the system can give without swapping: MemAvailable (Linux), else its free
    pages; None where neither is known."""
    try:
        with open("/proc/meminfo") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):  # no sysconf (Windows) or no such name
        return None


def check_limits(limits, renderer, settings, scene):
    """Refuse images larger than the driver's `limits` (its GL_MAX_* values, as moderngl's
    `info` gives them) allow: the camera's, the lights' map atlases, the LPV's volumes."""
    s = settings
    widest = min(limits["GL_MAX_TEXTURE_SIZE"], limits["GL_MAX_FRAMEBUFFER_WIDTH"])
    tallest = min(limits["GL_MAX_TEXTURE_SIZE"], limits["GL_MAX_FRAMEBUFFER_HEIGHT"])
    if s.width > widest or s.height > tallest:
        raise LPVError(f"A {s.width} x {s.height} image is larger than {renderer} can render ({widest} x "
                       f"{tallest} at most); lower the resolution.")
    widest, tallest = (min(side, limits["GL_MAX_RENDERBUFFER_SIZE"]) for side in (widest, tallest))
    for light in scene.lights:
        width, height = face_atlas_size(map_face_count(light, map_method(s.method)), s.rsm_resolution)
        if width > widest or height > tallest:
            raise LPVError(f"An RSM resolution of {s.rsm_resolution} makes {width} x {height} light maps, larger "
                           f"than {renderer} can render ({widest} x {tallest} at most); lower the RSM resolution.")
    side = indirect_method(s).longest_side(s)
    if side > limits["GL_MAX_3D_TEXTURE_SIZE"]:
        raise LPVError(f"A grid resolution of {s.lpv_resolution} needs volumes of {side} cells a side with "
                       f"indirect method {s.indirect_method}, more than {renderer} allows "
                       f"({limits['GL_MAX_3D_TEXTURE_SIZE']}); lower the LPV resolution.")


FLOAT_ATOMICS = "GL_NV_shader_atomic_float"
"""The extension the emitter grid's clustering adds floats with (shaders/emitter_bin.comp)."""


SOFTWARE_TEXTURE_BYTES = GIB
"""The largest texture llvmpipe makes (Mesa's LP_MAX_TEXTURE_SIZE): a larger one is
GL_OUT_OF_MEMORY, and nothing drawn into it."""


def check_emitter_grid(extensions, renderer, settings, scene, software=False):
    """Refuse a frame that needs the emitter grid on a driver without float atomics, or
    whose textures the software rasterizer (`software`) cannot make."""
    lamps = len(scene.lights) - len(mapped_lights(settings, scene))
    if settings.emitter_light != "grid" or not (scene.point_emitter_count or lamps):
        return
    if FLOAT_ATOMICS not in extensions:
        raise LPVError(f"{renderer} lacks {FLOAT_ATOMICS}, which the emitter grid needs for the scene's point "
                       f"emitters; set emitter_light to brute_force.")
    side = largest_texture_side(settings)
    if software and side ** 3 * GRID_TEXEL_BYTES > SOFTWARE_TEXTURE_BYTES:
        raise LPVError(f"An emitter grid resolution of {settings.emitter_grid_resolution} needs textures of {side}³ "
                       f"texels, {side ** 3 * GRID_TEXEL_BYTES / GIB:.0f} GiB each, more than {renderer} makes "
                       f"({SOFTWARE_TEXTURE_BYTES / GIB:.0f} GiB); lower the emitter grid resolution.")


def check_frame_fits(glc, settings, scene, passes=PASS_NAMES, display=False, held_bytes=0):
    """Refuse, before anything is allocated, a frame the driver's limits or the memory
    free cannot hold; `held_bytes` of GPU memory are already allocated for it (a
    pipeline's earlier frame) and are used again."""
    check_limits(glc.gl.info, glc.renderer, settings, scene)
    check_emitter_grid(glc.gl.extensions, glc.renderer, settings, scene, glc.is_software)
    available = available_host_bytes()
    if available is None:
        return
    gpu, host = frame_bytes(settings, scene, passes, display)
    size = f"A {settings.width} x {settings.height} frame"
    if glc.is_software and max(gpu - held_bytes, 0) + host > available:
        raise LPVError(f"{size} needs about {(gpu + host) / GIB:.1f} GiB of memory ({gpu / GIB:.1f} GiB of images "
                       f"and maps, which {glc.renderer.split(' (')[0]} keeps in host memory, and {host / GIB:.1f} GiB "
                       f"read back) but {available / GIB:.1f} GiB is free; lower the resolution, the RSM resolution "
                       f"or the number of lights.")
    if not glc.is_software and host > available:
        raise LPVError(f"{size} needs about {host / GIB:.1f} GiB of host memory for its images read back but "
                       f"{available / GIB:.1f} GiB is free; lower the resolution.")
