"""Temporary folders for the files a render writes (a Cycles render's EXR, the workers'
scratch space), made or refused in one sentence and removed afterwards."""
import shutil
import tempfile
from contextlib import contextmanager

from .errors import LPVError


def make_temporary_folder(prefix):
    """A new temporary folder named from `prefix` (the caller removes it), or one sentence."""
    try:
        return tempfile.mkdtemp(prefix=prefix)
    except OSError as error:
        raise LPVError(f"Cannot create a temporary folder for a Cycles render in "
                       f"'{tempfile.gettempdir()}' ({error.strerror}); set TMPDIR to a writable folder.") from error


@contextmanager
def temporary_folder(prefix="lpv_cycles_"):
    """A temporary folder for a Cycles render's file, removed afterwards."""
    folder = make_temporary_folder(prefix)
    try:
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)
