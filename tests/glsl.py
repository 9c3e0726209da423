"""Evaluate a GLSL compute shader over test inputs (for checking shader math against numpy)."""
import numpy as np

from lpv_preview.gpu.context import dispatch, preprocess


def evaluate(glc, source, inputs, outputs_per_input):
    """Run `source` (binding 0: vec4 inputs, binding 1: vec4 results, 64 invocations a group)
    over (n, 3 or 4) inputs; returns float64 results shaped (outputs_per_input, n, 4)."""
    inputs = np.asarray(inputs, dtype=np.float32)
    count = len(inputs)
    padded = np.zeros((count, 4), dtype=np.float32)
    padded[:, :inputs.shape[1]] = inputs
    program = glc.gl.compute_shader(preprocess(source))
    source_buffer = glc.gl.buffer(padded.tobytes())
    results = glc.gl.buffer(reserve=count * outputs_per_input * 16)
    source_buffer.bind_to_storage_buffer(0)
    results.bind_to_storage_buffer(1)
    dispatch(program, count, local=(64,))
    out = np.frombuffer(results.read(), dtype=np.float32).reshape(outputs_per_input, count, 4).astype(np.float64)
    for resource in (program, source_buffer, results):
        resource.release()
    return out
