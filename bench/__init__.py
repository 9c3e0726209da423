"""Measurement of the renderer: Table 1, the sweeps, their reports and the benchmarks page,
exact stand-in stages and time to equal error. numpy + moderngl over gpu/, never bpy:
it runs on the GPU machine from .npz scene files. Nothing in gpu/, addon/ or operators/
imports it (docs/architecture.md)."""
