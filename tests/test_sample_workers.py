"""Cycles sample workers (issue 18, first step): a border region renders the pixels the
whole image has there, and Dask workers lose no request when one dies mid-request. Real
bpy and Cycles, a real Dask cluster of local processes."""
import time

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview import demo  # noqa: E402
from lpv_preview.addon.cycles_samples import SampleRenderer  # noqa: E402
from lpv_preview.addon.sample_workers import SampleWorkers  # noqa: E402
from lpv_preview.gpu.errors import LPVError  # noqa: E402
from lpv_preview.sample_tasks import SampleRequest  # noqa: E402

SIZE = (32, 24)


@pytest.fixture(scope="module")
def cornell_blend(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("samples") / "cornell.blend")
    demo.build("cornell", resolution=SIZE)
    bpy.ops.wm.save_as_mainfile(filepath=path)
    return path


def test_a_region_has_the_pixels_of_the_whole_image(cornell_blend):
    renderer = SampleRenderer(cornell_blend)
    try:
        whole = renderer.render(SampleRequest((0, 0, *SIZE), SIZE, 4, seed=3))
        part = renderer.render(SampleRequest((8, 4, 20, 14), SIZE, 4, seed=3))
    finally:
        renderer.close()
    for name, image in part.passes.items():
        assert image.shape == (10, 12, 3)
        np.testing.assert_allclose(image, whole.passes[name][4:14, 8:20], rtol=1e-4, atol=1e-6, err_msg=name)
    assert whole.passes["Combined"].mean() > 0


def test_requests_out_of_the_image_are_refused():
    with pytest.raises(LPVError, match="out of range"):
        SampleRequest((0, 0, 40, 10), SIZE, 4)


def test_a_remote_scheduler_is_reached_over_tls_only(cornell_blend):
    with pytest.raises(LPVError, match="not a tls:// address"):
        SampleWorkers(cornell_blend, scheduler="tcp://192.0.2.1:8786")


def test_no_request_is_lost_when_a_worker_dies(cornell_blend):
    """Two local workers; one is killed while it renders; every request still returns."""
    requests = [SampleRequest((0, 0, *SIZE), SIZE, 64, seed=seed) for seed in range(6)]
    with SampleWorkers(cornell_blend, workers=2) as workers:
        futures = [workers.submit(request) for request in requests]
        deadline = time.time() + 60
        while time.time() < deadline and not any(workers.client.processing().values()):
            time.sleep(0.05)
        busy = next(address for address, tasks in workers.client.processing().items() if tasks)
        nanny = next(worker for worker in workers.cluster.workers.values() if worker.worker_address == busy)
        nanny.process.process.kill()
        results = workers.client.gather(futures)
    assert [result.request.seed for result in results] == list(range(6))
    assert all(result.passes["Combined"].shape == (SIZE[1], SIZE[0], 3) for result in results)
