"""The embedded GPU module: numpy + moderngl, never bpy.

It runs in the tests, on the command line and on the GPU machine without Blender.
"""
