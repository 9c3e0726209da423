"""The world on the GPU: its lighting as distant emitters drawn anew for each VPL pattern
(gpu/world.py `World.emitter_rows`), whose light every pixel gathers with visibility and
which bounce like any emitter's, and its background map, which the composite looks up
along each camera ray where the camera sees no surface."""
import numpy as np


class WorldLight:
    """A scene world's emitters and background texture, made again when the world, the
    count or the pattern (emitters) or the world (texture) change."""

    def __init__(self, glc):
        self.glc = glc
        self.emitters = None
        self.count = 0
        self.background = None
        self._emitters_key = self._background_key = None

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

    def resources(self):
        return tuple(held for held in (self.emitters, self.background) if held is not None)

    def release(self):
        for held in self.resources():
            held.release()
        self.emitters = self.background = None
        self._emitters_key = self._background_key = None
        self.count = 0
