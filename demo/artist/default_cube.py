"""Blender's default startup scene as it opens: the cube (its grey "Material"), the
1000 W point light, the camera and the dark grey world, all untouched but the resolution."""
from .shading import factory_scene


def build(resolution=(1920, 1080)):
    return factory_scene(resolution, keep_startup_objects=True)
