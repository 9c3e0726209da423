"""The world on the GPU: its lighting as distant emitters drawn anew for each VPL pattern
(gpu/world.py `World.emitter_rows`), whose light every pixel gathers with visibility and
which bounce like any emitter's, its background map, which the composite looks up
along each camera ray where the camera sees no surface, and its lighting map with its
mip chain, which glossy surfaces reflect (docs/method.md, "Specular light")."""
import numpy as np

from .emitter_bounce import flux_bound
from .keyed_cache import KeyedCache
from .world import SCENE_SHARE



def world_lights(scene, settings):
    """Whether the scene's world lights it: a world with any light and World Samples above 0."""
    return scene.world is not None and scene.world.lights_anything and settings.world_samples > 0


class WorldLight:
    """A scene world's emitters, made again when the world, the count or the pattern
    change, and its textures, made again when the world does."""

    def __init__(self, glc):
        self.glc = glc
        self.count = 0
        self.flux_bound = 0.0  # the largest channel of the emitters' summed flux that reaches the scene
        self._emitters, self._background, self._reflection = (KeyedCache(releases=True) for _ in range(3))

    @property
    def emitters(self):
        return self._emitters.value

    def sample(self, scene, count, pattern):
        """Draw `count` distant emitters of `scene.world` with the random numbers of `pattern`."""
        world = scene.world
        low, high = scene.bounds()

        def draw():
            rows = world.emitter_rows(count, pattern, (low + high) / 2, float(np.linalg.norm(high - low)))
            self.count, self.flux_bound = len(rows), flux_bound(rows) * SCENE_SHARE
            return self.glc.gl.buffer(rows.tobytes() if len(rows) else np.zeros((1, 3, 4), np.float32).tobytes())
        self._emitters.get((world.key(), count, pattern, tuple(low), tuple(high)), draw)

    def _map_texture(self, image, mipmaps):
        """An equirectangular map as an RGB float texture wrapping around in u, row 0
        looking down (GL's first row is the image's last)."""
        height, width = image.shape[:2]
        texture = self.glc.gl.texture((width, height), 3, np.ascontiguousarray(image[::-1], dtype=np.float32).tobytes(),
                                      dtype="f4")
        if mipmaps:
            texture.build_mipmaps()
        texture.filter = (self.glc.gl.LINEAR_MIPMAP_LINEAR if mipmaps else self.glc.gl.LINEAR, self.glc.gl.LINEAR)
        texture.repeat_x, texture.repeat_y = True, False
        return texture

    def background_texture(self, world):
        """The world's background map, linear-filtered."""
        return self._background.get(world.key(), lambda: self._map_texture(world.background, mipmaps=False))

    def reflection_texture(self, world):
        """The world's lighting map (what reflected rays see, as Cycles' glossy rays do)
        with its mip chain: the composite reads it at a level of the surface's roughness
        (a box-filtered chain, not a GGX convolution)."""
        return self._reflection.get(world.key(), lambda: self._map_texture(world.lighting, mipmaps=True))

    def resources(self):
        return tuple(cache.value for cache in (self._emitters, self._background, self._reflection)
                     if cache.value is not None)

    def release(self):
        for cache in (self._emitters, self._background, self._reflection):
            cache.clear()
        self.count, self.flux_bound = 0, 0.0
