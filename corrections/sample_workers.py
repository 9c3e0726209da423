"""Cycles sample workers on Dask distributed: each worker process keeps one renderer (the
caller's: addon/sample_renderer.py) per .blend, so the scene is loaded once a process;
requests go out as Dask tasks, and a worker that dies mid-request loses nothing, the
scheduler hands its tasks to another.

`SampleWorkers(blend, open_renderer, workers=N)` starts a local cluster listening on the
loopback address only; `SampleWorkers(blend, open_renderer, scheduler="tls://HOST:PORT",
security=...)` joins a studio's cluster, over TLS only: a Dask scheduler runs whatever
code it is sent, so it is never reached in the clear (README, "Cycles sample workers").
"""
import logging

from ..gpu.errors import LPVError, first_line
from ..gpu.temporary_folders import make_temporary_folder, remove_temporary_folder
from .sample_request import SampleRequest
from .worker_task import open_blend, render_request

WORKER_DEATHS_ALLOWED = 3
"""Worker deaths a request may see before it is given up (Dask's allowed-failures)."""


TLS_SETTINGS = ("distributed.comm.tls.ca-file, distributed.comm.tls.client.cert and distributed.comm.tls.client.key "
                "in Dask's configuration (README, \"Corrections toward Cycles\")")
"""Where a user gives the certificates that reach a studio's scheduler."""


def check_scheduler(scheduler):
    """Refuse, before any work, a scheduler address that is not TLS or that Dask's
    configuration gives no certificates for (Dask would fail deep in its connection)."""
    if scheduler is None:
        return
    if not scheduler.startswith("tls://"):
        raise LPVError(f"The Dask scheduler '{scheduler}' is not a tls:// address; a scheduler runs whatever code it "
                       f"is sent, so reach it over TLS only (see the README).")
    check_tls_configuration(scheduler)


def check_tls_configuration(scheduler):
    """Refuse a TLS scheduler when Dask's configuration has no CA file, client certificate
    and key, or ones that cannot be loaded; a configured security loader gives its own."""
    try:
        import dask
        from distributed.security import Security
    except ImportError:
        raise LPVError("The Cycles sample workers need Dask distributed, which this Python lacks; install "
                       "requirements.txt (bash scripts/setup.sh).") from None
    if dask.config.get("distributed.client.security-loader", None):
        return
    try:
        context = Security().get_connection_args("client")["ssl_context"]
    except (OSError, ValueError) as error:  # a missing or unreadable file, a bad key, an unknown TLS version
        raise LPVError(f"Dask's TLS certificates for the scheduler '{scheduler}' cannot be loaded "
                       f"({first_line(error)}); fix {TLS_SETTINGS}.") from None
    if context is None:
        raise LPVError(f"The Dask scheduler '{scheduler}' needs TLS certificates, which Dask's configuration lacks; "
                       f"set {TLS_SETTINGS}.")


class SampleWorkers:
    """A Dask client and, for `workers`, the local cluster it owns; each worker opens the
    .blend with `open_renderer(blend_path)`, a function it imports by name (one that
    imports bpy when called: addon/sample_renderer.py)."""

    def __init__(self, blend_path, open_renderer, workers=None, scheduler=None, security=None):
        check_scheduler(scheduler)
        if scheduler is None and (workers is None or workers < 1):
            raise LPVError(f"Start 1 or more Cycles sample workers, not {workers}.")
        try:
            import dask
            from distributed import Client, LocalCluster
        except ImportError:
            raise LPVError("The Cycles sample workers need Dask distributed, which this Python lacks; install "
                           "requirements.txt (bash scripts/setup.sh).") from None
        self.blend_path, self.open_renderer = blend_path, open_renderer
        self.cluster = self.client = None
        # a local cluster's files (Dask's scratch space, the workers' renders) in one folder,
        # removed on close even when a worker is stopped before it cleans up
        self.folder = make_temporary_folder("lpv_sample_workers_") if scheduler is None else None
        local = {"temporary-directory": self.folder} if self.folder else {}
        with dask.config.set({"distributed.scheduler.allowed-failures": WORKER_DEATHS_ALLOWED, **local}):
            try:
                if scheduler is not None:
                    self.client = Client(scheduler, security=security, timeout="20s")
                else:
                    # silence_logs: a worker that heartbeats after the scheduler closed (a close
                    # under load, as on Ctrl-C) would print Dask's traceback on the user's terminal;
                    # the workers' errors come back through their futures
                    self.cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                                host="127.0.0.1", dashboard_address=None, silence_logs=logging.CRITICAL,
                                                env={name: self.folder for name in ("TMPDIR", "TEMP", "TMP")})
                    self.client = Client(self.cluster)
            except (OSError, RuntimeError, TimeoutError) as error:
                self.close()
                if scheduler is not None:
                    raise LPVError(f"The Dask scheduler at '{scheduler}' could not be reached ({first_line(error)}); "
                                   f"check that it runs there and accepts the certificates of {TLS_SETTINGS}.") \
                        from None
                raise LPVError(f"The Cycles sample workers could not start ({workers} local workers: "
                               f"{first_line(error)}); they need a Python with the bpy module and Dask "
                               f"(bash scripts/setup.sh).") from None
        # a local worker is one core: Cycles alone would take them all in each (start as many
        # workers as cores); a remote worker's own machine decides
        self.threads = 1 if self.cluster is not None else None

    def open_everywhere(self):
        """Have every worker open the .blend now, so the first requests wait for none."""
        try:
            self.client.run(open_blend, self.open_renderer, self.blend_path)
        except Exception as error:  # whatever the worker raised, pickled back
            raise LPVError(f"The Cycles sample workers could not open '{self.blend_path}': {first_line(error)}.") \
                from None

    def submit(self, request, **placement):
        """A Dask future of the SampleResult of `request` (`placement`: Dask's, such as `workers`)."""
        return self.client.submit(render_request, self.open_renderer, self.blend_path, request, self.threads,
                                  pure=False, **placement)

    def settle(self, resolution):
        """Wait until every worker has ended what it renders: a cancelled request runs to its
        end, and a timed run after it would begin with busy workers. A 1-pixel request of
        `resolution` is queued on each worker's every thread and waited for."""
        futures = [self.submit(SampleRequest((0, 0, 1, 1), resolution, 1), workers=[address])
                   for address, threads in self.client.nthreads().items() for _ in range(threads)]
        self.client.gather(futures)

    def close(self):
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()
        if self.folder is not None:
            remove_temporary_folder(self.folder)

    def __enter__(self):
        return self

    def __exit__(self, *_):
        self.close()
