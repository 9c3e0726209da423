"""Small scenes made of arrays for the GPU tests (the demo scenes need bpy)."""
from lpv_preview.bench.synthetic import room_scene  # noqa: F401  (the tests' room is the benchmarks' one)
