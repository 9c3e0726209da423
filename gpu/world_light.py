"""The world on the GPU: its lighting as distant emitters drawn anew for each VPL pattern
(gpu/world.py `World.emitter_rows`), whose light every pixel gathers with visibility and
which bounce like any emitter's, its background map, which the composite looks up
along each camera ray where the camera sees no surface, and its lighting map with its
mip chain, which glossy surfaces reflect (docs/method.md, "Specular light")."""
import numpy as np


class WorldLight:
    """A scene world's emitters and background texture, made again when the world, the
    count or the pattern (emitters) or the world (texture) change."""

    def __init__(self, glc):
        self.glc = glc
        self.emitters = None
        self.count = 0
        self.background = self.reflection = None
        self._emitters_key = self._background_key = self._reflection_key = None

    def sample(self, scene, count, pattern):
        """Draw `count` distant emitters of `scene.world` with the random numbers of `pattern`."""
        world = scene.world
        low, high = scene.bounds()
        key = (world.key(), count, pattern, tuple(low), tuple(high))
        if key == self._emitters_key:
            return
        rows = world.emitter_rows(count, pattern, (low + high) / 2, float(np.linalg.norm(high - low)))
        if self.emitters is not None:
            self.emitters.release()
            self.emitters = None
        self.count = len(rows)
        self.emitters = self.glc.gl.buffer(rows.tobytes() if len(rows) else np.zeros((1, 3, 4), np.float32).tobytes())
        self._emitters_key = key

    def background_texture(self, world):
        """The world's background map as a linear-filtered RGB texture, row 0 looking down
        (GL's first row is the image's last)."""
        if world.key() != self._background_key:
            if self.background is not None:
                self.background.release()
            height, width = world.background.shape[:2]
            self.background = self.glc.gl.texture((width, height), 3, np.ascontiguousarray(
                world.background[::-1], dtype=np.float32).tobytes(), dtype="f4")
            self.background.filter = (self.glc.gl.LINEAR, self.glc.gl.LINEAR)
            self.background.repeat_x, self.background.repeat_y = True, False
            self._background_key = world.key()
        return self.background

    def reflection_texture(self, world):
        """The world's lighting map (what reflected rays see, as Cycles' glossy rays do)
        as an RGB texture with its mip chain, row 0 looking down: the composite reads it
        at a level of the surface's roughness (a box-filtered chain, not a GGX convolution)."""
        if world.key() != self._reflection_key:
            if self.reflection is not None:
                self.reflection.release()
            height, width = world.lighting.shape[:2]
            self.reflection = self.glc.gl.texture((width, height), 3, np.ascontiguousarray(
                world.lighting[::-1], dtype=np.float32).tobytes(), dtype="f4")
            self.reflection.build_mipmaps()
            self.reflection.filter = (self.glc.gl.LINEAR_MIPMAP_LINEAR, self.glc.gl.LINEAR)
            self.reflection.repeat_x, self.reflection.repeat_y = True, False
            self._reflection_key = world.key()
        return self.reflection

    def resources(self):
        return tuple(held for held in (self.emitters, self.background, self.reflection) if held is not None)

    def release(self):
        for held in self.resources():
            held.release()
        self.emitters = self.background = self.reflection = None
        self._emitters_key = self._background_key = self._reflection_key = None
        self.count = 0
