"""Corrections toward Cycles (seed 001, corrective texturing): the sample requests, the
workers that render them on Dask, the queue that picks them, the layers that keep their
samples over camera moves and the reconstruction along the preview's G-buffer. numpy and
Dask, never bpy: the Blender side hands in its renderer (README.md)."""
