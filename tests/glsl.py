"""Evaluate GLSL expressions over test inputs on the GPU (to check shader math against numpy)."""
import numpy as np

from lpv_preview.gpu.context import dispatch, preprocess

SHADER = """#version 450 core
{includes}
{functions}
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Inputs {{ vec4 inputs[]; }};
layout(std430, binding = 1) writeonly buffer Results {{ vec4 results[]; }};
void main() {{
    uint i = gl_GlobalInvocationID.x;
    vec4 x = inputs[i];
{stores}
}}
"""


def evaluate(glc, include, expressions, inputs, functions=""):
    """Each GLSL vec4 expression of `x` (an input, padded to vec4), with shaders/`include`
    (a name or names) included and then `functions`' GLSL, over (n, 3 or 4) inputs (n a
    multiple of 64); returns float64 results shaped (len(expressions), n, 4)."""
    inputs = np.asarray(inputs, dtype=np.float32)
    count = len(inputs)
    padded = np.zeros((count, 4), dtype=np.float32)
    padded[:, :inputs.shape[1]] = inputs
    stores = "\n".join(f"    results[i + {k}u * gl_NumWorkGroups.x * 64u] = {expression};"
                       for k, expression in enumerate(expressions))
    names = (include,) if isinstance(include, str) else include
    includes = "\n".join(f'#include "{name}"' for name in names)
    program = glc.gl.compute_shader(preprocess(SHADER.format(includes=includes, functions=functions, stores=stores)))
    source_buffer = glc.gl.buffer(padded.tobytes())
    results = glc.gl.buffer(reserve=count * len(expressions) * 16)
    source_buffer.bind_to_storage_buffer(0)
    results.bind_to_storage_buffer(1)
    dispatch(program, count, local=(64,))
    out = np.frombuffer(results.read(), dtype=np.float32).reshape(len(expressions), count, 4).astype(np.float64)
    for resource in (program, source_buffer, results):
        resource.release()
    return out
