"""The seed's master: keeps the Cycles sample workers busy with the priority queue's
requests for the view at rest, adds what comes back to the corrections, and rebuilds the
corrected frame when asked (layers.py, reconstruction.py, request_queue.py).

A view is a gpu Camera with its preview and G-buffer (gpu/shade.py GBufferRecord) and the camera's world matrix the
workers render with; a new view keeps the corrections of the earlier ones that still
apply. Results of a view the camera left still go into that view's layer.
"""
import time

import numpy as np

from ..gpu.capacity import GIB, available_host_bytes
from ..gpu.errors import LPVError, first_line
from .layers import Corrections
from .request_queue import RequestQueue
from .sample_request import SampleRequest

REQUESTS_PER_WORKER = 2
"""Requests kept in flight a worker: the next one is there when one ends."""
FIRST_SEED = 1000
"""Seeds of the requests count up from here, apart from the references' (0) and the peers' (1)."""
QUEUE_SECONDS = 0.5
"""While samples come, the queue learns the reconstruction's errors this often..."""
QUEUE_SHARE = 0.1
"""...or less, so that its rebuilds take at most this share of the master's time (a rebuild
at 1080p takes seconds)."""
REBUILD_PIXEL_SECONDS = 5e-6
"""A view's first rebuild's seconds a pixel (its edges made too; numpy on one core) until one
is timed: a timed run stops receiving that much before its time, so that its last frame is
ready as the time is up..."""
RECEIVE_SHARE = 0.5
"""...but receives for at least this share of its time, however long a rebuild."""
CAPACITY_SECONDS = 10.0
"""How often the cluster is asked how many workers it has (a studio's may grow)."""
CORRECTION_BYTES_PER_PIXEL = 1000
"""What the corrections toward Cycles  hold a pixel beyond the process's
own: a view's layer, the filter's edges at every scale and a rebuild's arrays (a process's
peak grew by about 1,000 bytes a pixel from 960×540 to 1920×1080)."""


def check_corrections_fit(width, height):
    """Refuse corrections of a `width` × `height` image that would not fit in the memory
    free now, before their workers start (their own scenes are not counted)."""
    needed, available = width * height * CORRECTION_BYTES_PER_PIXEL, available_host_bytes()
    if available is not None and needed > available:
        raise LPVError(f"Corrections of a {width} x {height} image need about {needed / GIB:.1f} GiB of memory but "
                       f"{available / GIB:.1f} GiB is free; render it smaller, or without --correct-seconds.")


class Corrector:
    """Corrections of one scene from `workers` (sample_workers.py SampleWorkers), at
    the animation's frame `scene_frame` (None: where the workers' scene is); `rebuild_seconds`:
    how long a rebuild of such a view took before (None: not known)."""

    def __init__(self, workers, scene_frame=None, rebuild_seconds=None):
        self.workers = workers
        self.scene_frame = scene_frame
        self.corrections = Corrections()
        self.in_flight = {}  # future -> (view key, the queue that asked, region, samples a pixel)
        self.seed = FIRST_SEED
        self.view_key = self.queue = self.camera_matrix = self.projection = None
        self.resolution = None
        self.samples_received = self.requests_received = 0
        self.started = self.last_received = None  # when the first request went, the last samples came
        self.updated = (0.0, 0)  # when the queue last learnt the errors, and the samples then
        self.rebuild_seconds = rebuild_seconds  # how long the last rebuild of a frame took
        self.capacity = (-CAPACITY_SECONDS, 1)  # (when asked, requests in flight wanted)

    def rest(self, key, camera, camera_matrix, preview, gbuffer, projection=None, settings=None):
        """The camera rests at the view `key`: its gpu Camera, the world matrix and the
        projection Cycles renders it with (4 × 4 nested tuples; None: the scene camera's),
        its preview ((h, w, 3)) of the preview's `settings` and its GBufferRecord. Returns the
        frame corrected by what the corrections hold already; requests go out."""
        self.corrections.view(key, camera, gbuffer, preview, settings)
        if key != self.view_key:
            self.view_key, self.camera_matrix, self.projection = key, camera_matrix, projection
            self.resolution = gbuffer.size
            self.queue = RequestQueue(self.resolution)
            if not self.corrections.layers:  # nothing to gather: the first requests cover the view meanwhile
                self.fill()
        frame = self.frame()
        self.fill()
        return frame

    def frame(self):
        """The corrected frame of the view at rest (a reconstruction.py Reconstruction); the
        queue learns its errors."""
        started = time.perf_counter()
        reconstruction = self.corrections.reconstruct(self.view_key)
        own = self.corrections.layers.get(self.view_key)
        self.queue.update(reconstruction.error, reconstruction.samples,
                          own.samples if own is not None else np.zeros_like(reconstruction.samples))
        self.updated = (time.perf_counter(), self.samples_received)
        if reconstruction.samples.any():  # a rebuild, not the preview alone
            self.rebuild_seconds = self.updated[0] - started
        return reconstruction

    def _rebuild_estimate(self):
        """How long the next rebuild is expected to take."""
        if self.rebuild_seconds is not None:
            return self.rebuild_seconds
        return REBUILD_PIXEL_SECONDS * self.resolution[0] * self.resolution[1]

    def fill(self):
        """Send requests until every worker has REQUESTS_PER_WORKER."""
        now = time.perf_counter()
        if self.started is None:
            self.started = now
        if now - self.capacity[0] >= CAPACITY_SECONDS:
            self.capacity = (now, REQUESTS_PER_WORKER * max(1, sum(self.workers.client.nthreads().values())))
        while len(self.in_flight) < self.capacity[1]:
            asked = self.queue.next()
            if asked is None:  # every tile is done
                return
            region, spp = asked
            request = SampleRequest(region, self.resolution, spp, self.seed, self.camera_matrix, self.projection,
                                    scene_frame=self.scene_frame)
            self.seed += 1
            self.in_flight[self.workers.submit(request)] = (self.view_key, self.queue, region, spp)

    def receive(self, timeout=None):
        """Wait up to `timeout` seconds (None: until one comes) for results and add them;
        returns how many came. A request that failed on its worker (after Dask's retries)
        is refused in one sentence."""
        from distributed import wait
        self.fill()
        if not self.in_flight:
            time.sleep(timeout or 0.0)
            return 0
        done = [future for future in self.in_flight if future.done()]
        if not done and timeout != 0:
            try:
                done = wait(list(self.in_flight), timeout=timeout, return_when="FIRST_COMPLETED").done
            except TimeoutError:
                return 0
        for future in done:
            key, queue, region, spp = self.in_flight.pop(future)
            if future.status != "finished":
                queue.done(region, spp)
                raise LPVError(f"A Cycles sample worker failed: {first_line(future.exception())}.")
            result = future.result()
            queue.done(region, spp, result.seconds)
            if self.corrections.add(key, region, result.passes["Combined"], spp):
                self.samples_received += result.passes["Combined"].shape[0] * result.passes["Combined"].shape[1] * spp
                self.requests_received += 1
                self.last_received = time.perf_counter()
        return len(done)

    def run(self, seconds, frames_at=()):
        """Receive for `seconds`, rebuilding the frame at each of the times `frames_at`
        (seconds from now; what a viewport redraw would show then) and, for the queue,
        every QUEUE_SECONDS while samples come (QUEUE_SHARE); yields (seconds since the
        start, Reconstruction) for each of `frames_at` before the last and at the end, the
        last as the time is up: receiving stops a rebuild's time before (RECEIVE_SHARE)."""
        start = time.perf_counter()
        pending = sorted(frames_at)
        while True:
            elapsed, estimate = time.perf_counter() - start, self._rebuild_estimate()
            until = max(seconds - estimate, RECEIVE_SHARE * seconds)
            pending = [at for at in pending if at < until]
            if elapsed >= until:
                break
            next_stop = min([until, *pending[:1]]) - elapsed
            self.receive(timeout=max(0.0, min(next_stop, 0.05)))  # the workers are kept busy first
            elapsed = time.perf_counter() - start
            if pending and elapsed >= pending[0]:
                pending = [at for at in pending if at > elapsed]
                frame = self.frame()
                yield time.perf_counter() - start, frame
            elif (elapsed + estimate < until and self.samples_received > self.updated[1]
                  and time.perf_counter() - self.updated[0] >= max(QUEUE_SECONDS, estimate / QUEUE_SHARE)):
                self.frame()
        frame = self.frame()
        yield time.perf_counter() - start, frame

    def stats(self, reconstruction=None):
        """Samples received, samples a second from the first request to the last samples
        (not counting a final rebuild, or a view done asking), the estimated error."""
        elapsed = self.last_received - self.started if self.last_received is not None else 0.0
        stats = {"correction_samples": self.samples_received, "correction_requests": self.requests_received,
                 "correction_samples_per_second": self.samples_received / elapsed if elapsed > 0 else 0.0}
        if reconstruction is not None:
            stats["correction_estimated_error"] = reconstruction.estimated_error
        return stats

    def cancel(self):
        """Drop the requests in flight."""
        for future, (_, queue, region, spp) in self.in_flight.items():
            future.cancel()
            queue.done(region, spp)
        self.in_flight.clear()


def rendered_passes(passes):
    """The passes a corrected frame is rendered with (the combined one is corrected), and
    those it is written with: its preview beside them."""
    rendered = tuple(dict.fromkeys(("combined", *passes)))
    return rendered, (*rendered, "preview")


def correct(workers, pipeline, scene, frame, seconds, scene_frame, rebuild_seconds=None):
    """Correct the combined pass of `frame`, which `pipeline` rendered last from the gpu
    Scene `scene` at the animation's frame `scene_frame`, toward Cycles for `seconds` with
    `workers` (`rebuild_seconds`: as the last corrected frame's rebuild took, if known);
    the uncorrected image becomes the pass `preview`. Returns the statistics of what came,
    also added to the frame's."""
    gbuffer = pipeline.read_gbuffer(scene)
    corrector = Corrector(workers, scene_frame, rebuild_seconds)
    corrector.rest(scene.camera.key(), scene.camera, None, frame.passes["combined"], gbuffer)
    for _, reconstruction in corrector.run(seconds):
        pass
    corrector.cancel()
    frame.passes["preview"] = frame.passes["combined"]
    frame.passes["combined"] = reconstruction.image
    stats = {**corrector.stats(reconstruction), "correction_rebuild_seconds": corrector.rebuild_seconds}
    frame.stats.update(stats)
    return stats
