"""Reading Blender's multi-layer EXRs, which Blender 5.0 writes as one part per pass."""
import OpenImageIO as oiio


def exr_parts(path):
    """{channel name: (height, width) array, top row first} over every part of an EXR."""
    image = oiio.ImageInput.open(str(path))
    channels, part = {}, 0
    while image.seek_subimage(part, 0):
        pixels = image.read_image(part, 0, 0, image.spec().nchannels, "float")
        for index, name in enumerate(image.spec().channelnames):
            channels[name] = pixels[..., index]
        part += 1
    image.close()
    return channels
