"""What part of a frame a render writes, and with what alpha: the render region (Ctrl-B),
cropped or not, and Film Transparent, as Blender's F12 writes them."""
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class OutputLayout:
    """A frame of `size` (width, height) written whole, or only its `region` (x0, y0, x1,
    y1: columns x0..x1-1 and rows y0..y1-1, row 0 at the top): as an image of the
    region's size when `crop`, else at full size, nothing outside the region (alpha 0).
    With `transparent`, the combined image's alpha is the frame's coverage (0 where the
    camera sees the background); else it is opaque."""

    size: tuple
    region: tuple = None
    crop: bool = True
    transparent: bool = False

    @staticmethod
    def of_border(size, border, crop, transparent):
        """The layout of a render border given as Blender stores it, (min x, max x, min y,
        max y) fractions of the frame with y from the bottom (None: no border), its pixels
        truncated as Blender's are."""
        if border is None:
            return OutputLayout(tuple(size), None, crop, transparent)
        width, height = size
        min_x, max_x, min_y, max_y = border
        x0, x1 = int(min_x * width), int(max_x * width)
        bottom, top = int(min_y * height), int(max_y * height)
        region = (x0, height - top, x1, height - bottom)
        if region == (0, 0, width, height):
            region = None
        return OutputLayout(tuple(size), region, crop, transparent)

    @property
    def region_size(self):
        """The region's (width, height): what Blender's RenderResult holds."""
        if self.region is None:
            return self.size
        x0, y0, x1, y1 = self.region
        return x1 - x0, y1 - y0

    @property
    def image_size(self):
        """The (width, height) of the written image."""
        return self.region_size if self.crop else self.size

    @property
    def empty(self):
        """Whether the region holds no pixel (a border narrower than a pixel)."""
        width, height = self.region_size
        return width <= 0 or height <= 0

    def region_of(self, image):
        """The region of a (height, width, ...) top-row-first image of the whole frame."""
        if self.region is None:
            return image
        x0, y0, x1, y1 = self.region
        return image[y0:y1, x0:x1]

    def placed(self, region_image):
        """A region's image as written: itself when cropped, else at the frame's place in
        an image of the full size, zero outside."""
        if self.crop or self.region is None:
            return region_image
        x0, y0, x1, y1 = self.region
        width, height = self.size
        full = np.zeros((height, width) + region_image.shape[2:], dtype=region_image.dtype)
        full[y0:y1, x0:x1] = region_image
        return full

    def written(self, passes, coverage):
        """The frame's `passes` ({name: (height, width, 3)}) as the render writes them: the
        region (placed), the combined one with an alpha channel when transparent (its
        `coverage`, (height, width)); for the region alone (Blender's RenderResult), use
        `region_of` and `combined_alpha`."""
        images = {name: self.placed(self.region_of(image)) for name, image in passes.items()}
        if self.transparent and "combined" in images:
            alpha = self.placed(self.region_of(coverage))
            images["combined"] = np.concatenate([images["combined"], alpha[..., None]], axis=2)
        elif self.region is not None and not self.crop and "combined" in images:
            inside = self.placed(np.ones(self.region_size[::-1], np.float32))
            images["combined"] = np.concatenate([images["combined"], inside[..., None]], axis=2)
        return images

    def combined_alpha(self, coverage):
        """The alpha of the region's combined pixels (Blender's Combined pass)."""
        region = self.region_of(coverage)
        return region if self.transparent else np.ones_like(region)
