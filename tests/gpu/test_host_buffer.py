"""The viewport's rows through a mapped buffer in the host's memory: what a shader wrote,
every byte, in whatever parts the threads copy; and large arrays written to the GPU
through one: every byte where it belongs."""
import numpy as np

from lpv_preview.gpu import context
from lpv_preview.gpu.host_buffer import HostBuffer, UploadBuffer
from lpv_preview.gpu.shade import DISPLAY_CHANNELS, FrameTargets

WRITE_INDICES = """#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Rows { float rows[]; };
uniform uint count;
uniform float frame;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < count) rows[i] = float(i) + frame;
}
"""


def test_a_shaders_rows_reach_the_host_whole_frame_after_frame(glc):
    count = 1_000_003  # parts of unequal sizes
    host = HostBuffer.make(glc.gl, count * 4)
    assert host is not None, f"{glc.renderer} maps no buffer of client storage"
    program = glc.gl.compute_shader(WRITE_INDICES)
    try:
        out = bytearray(count * 4)
        for frame in (0.0, 7.0):  # the second frame overwrites the first in place
            host.bind_to_storage_buffer(0)
            program["count"], program["frame"] = count, frame
            program.run((count + 63) // 64)
            host.read_into(out)
            rows = np.frombuffer(out, dtype=np.float32)
            np.testing.assert_array_equal(rows, np.arange(count, dtype=np.float32) + np.float32(frame))
    finally:
        program.release()
        host.release()


def test_the_frame_targets_keep_the_viewports_rows_in_the_host_buffer(glc):
    targets = FrameTargets(glc.gl, 32, 24)
    try:
        assert isinstance(targets.display_buffer(), HostBuffer)
        assert targets.display_buffer().size == 32 * 24 * DISPLAY_CHANNELS * 4
        assert targets.display not in targets.resources()  # host memory, not the GPU's
    finally:
        targets.release()


def test_without_a_mapped_buffer_the_rows_are_read_back_the_same(glc, monkeypatch):
    """Where the driver maps no buffer, the composite's rows come through an ordinary one."""
    from lpv_preview.bench.synthetic import room_scene
    from lpv_preview.gpu.pipeline import Pipeline
    from lpv_preview.gpu.settings import Settings
    settings = Settings(width=32, height=24, rsm_resolution=64, vpls_per_light=128, lpv_resolution=8)
    scene = room_scene(4)
    rows = []
    for mapped in (True, False):
        if not mapped:
            monkeypatch.setattr(HostBuffer, "make", classmethod(lambda cls, gl, size: None))
        pipeline = Pipeline(settings, glc)
        try:
            out = np.empty(32 * 24 * DISPLAY_CHANNELS, np.float32)
            pipeline.render(scene, passes=(), display_into=out)
            assert isinstance(pipeline.targets.display, HostBuffer) == mapped
            rows.append(out)
        finally:
            pipeline.release()
    assert rows[0].max() > 0
    np.testing.assert_array_equal(rows[0], rows[1])


def test_large_writes_reach_the_gpu_whole_through_the_upload_buffer_in_parts_or_without_it(glc, monkeypatch):
    """GLContext.write: arrays of STAGED_WRITE_BYTES and more go through its UploadBuffer, in
    parts where they outgrow it (here 512 KB), again and again into the same buffer; where
    no buffer maps, through the driver: the same bytes at the same offset each way."""
    rng = np.random.default_rng(1)
    monkeypatch.setattr(context, "UPLOAD_BYTES_MOST", 1 << 19)
    offset = 64
    for mapped in (True, False):
        if not mapped:
            monkeypatch.setattr(UploadBuffer, "make", classmethod(lambda cls, gl, size: None))
        monkeypatch.setattr(glc, "_upload", None)
        target = glc.gl.buffer(reserve=offset + 2_000_000)
        try:
            for _ in range(2):
                arrays = [rng.random(300_001).astype(np.float32), rng.integers(0, 2 ** 32, 77_777, dtype=np.uint32)]
                total = sum(array.nbytes for array in arrays)
                assert total >= context.STAGED_WRITE_BYTES
                glc.write(target, arrays, offset)
                assert target.read(size=total, offset=offset) == b"".join(array.tobytes() for array in arrays)
            assert isinstance(glc._upload, UploadBuffer) == mapped
        finally:
            if glc._upload:
                glc._upload.release()
            target.release()
