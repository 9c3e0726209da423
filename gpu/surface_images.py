"""The scene's images on the GPU: one mip-mapped texture array that the G-buffer and the
lights' maps sample per pixel and per texel (shaders/surface.glsl).

A texture array holds layers of one size, so every image is resampled on the CPU to a
square of the largest image's side (rounded up to a power of two), at most
MAX_IMAGE_SIZE, and smaller while the array would pass IMAGE_BUDGET_BYTES; UVs address an
image whatever its shape, so a square layer loses no mapping, only resolution where an
image was larger. Pixels are linear half floats: mip-maps average light, not sRGB codes.
A layer's alpha is its image's where the image brings one (a material's alpha reads it,
shaders/surface.glsl), else 1.
"""
import moderngl
import numpy as np

MAX_IMAGE_SIZE = 1024
IMAGE_BUDGET_BYTES = 512 * 2 ** 20
BYTES_PER_TEXEL = 8 * 4 / 3  # RGBA half floats, with the mip chain
IMAGE_UNIT = 7  # the texture unit the raster passes sample images from


def layer_size(images):
    """The side of the array's square layers for `images`."""
    largest = max((max(image.pixels.shape[:2]) for image in images), default=1)
    size = min(MAX_IMAGE_SIZE, 1 << max(0, int(np.ceil(np.log2(max(largest, 1))))))
    while size > 1 and size * size * BYTES_PER_TEXEL * len(images) > IMAGE_BUDGET_BYTES:
        size //= 2
    return size


def resampled(pixels, size):
    """(H, W, C) pixels, top row first, as (size, size, C) float32 bottom row first (GL's
    order): halved by 2x2 box filters while at least twice too large, then bilinear."""
    image = np.asarray(pixels, dtype=np.float32)[::-1]
    while image.shape[0] >= 2 * size or image.shape[1] >= 2 * size:
        rows, columns = image.shape[0] // 2 * 2 or 1, image.shape[1] // 2 * 2 or 1
        image = image[:rows, :columns]
        if rows > 1:
            image = 0.5 * (image[0::2] + image[1::2])
        if columns > 1:
            image = 0.5 * (image[:, 0::2] + image[:, 1::2])
    height, width = image.shape[:2]
    y = np.clip((np.arange(size) + 0.5) * height / size - 0.5, 0, height - 1)
    x = np.clip((np.arange(size) + 0.5) * width / size - 0.5, 0, width - 1)
    y0, x0 = np.floor(y).astype(int), np.floor(x).astype(int)
    y1, x1 = np.minimum(y0 + 1, height - 1), np.minimum(x0 + 1, width - 1)
    fy, fx = (y - y0)[:, None, None], (x - x0)[None, :, None]
    top = image[y0][:, x0] * (1 - fx) + image[y0][:, x1] * fx
    bottom = image[y1][:, x0] * (1 - fx) + image[y1][:, x1] * fx
    return (top * (1 - fy) + bottom * fy).astype(np.float32)


class SurfaceImages:
    """The texture array of a scene's images (one white layer when it has none)."""

    def __init__(self, gl, images):
        size = layer_size(images)
        layers = [resampled(image.pixels, size) for image in images] or [np.ones((1, 1, 3), np.float32)]
        rgba = np.ones((len(layers), size, size, 4), dtype=np.float16)
        for index, layer in enumerate(layers):
            rgba[index, ..., :layer.shape[2]] = layer[..., :4]
        self.size = size
        self.texture = gl.texture_array((size, size, len(layers)), 4, rgba.tobytes(), dtype="f2")
        self.texture.build_mipmaps()
        self.texture.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        self.texture.anisotropy = 8.0

    def bind(self, *programs):
        """Bind the array to IMAGE_UNIT for `programs`' `surface_images` sampler."""
        self.texture.use(location=IMAGE_UNIT)
        for program in programs:
            if "surface_images" in program:
                program["surface_images"] = IMAGE_UNIT

    def resources(self):
        return (self.texture,)

    def release(self):
        self.texture.release()
