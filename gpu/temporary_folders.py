"""Temporary folders for the files a render writes (a Cycles render's EXR, the workers'
scratch space), made or refused in one sentence and removed afterwards."""
import shutil
import tempfile
from contextlib import contextmanager

from .ctrl_c import ctrl_c_held
from .errors import LPVError


def make_temporary_folder(prefix):
    """A new temporary folder named from `prefix` (the caller removes it), or one sentence."""
    try:
        return tempfile.mkdtemp(prefix=prefix)
    except OSError as error:
        raise LPVError(f"Cannot create a temporary folder for a Cycles render in "
                       f"'{tempfile.gettempdir()}' ({error.strerror}); set TMPDIR to a writable folder.") from error


def remove_temporary_folder(folder):
    """Remove a temporary folder and what it holds; a Ctrl-C that comes meanwhile waits
    until it is gone (cut in two, the folder would stay behind)."""
    with ctrl_c_held():
        shutil.rmtree(folder, ignore_errors=True)


@contextmanager
def temporary_folder(prefix="lpv_cycles_"):
    """A temporary folder for a Cycles render's file, removed afterwards, also on Ctrl-C:
    one that comes while it is made or removed waits until that is done."""
    folder = None
    try:
        with ctrl_c_held():
            folder = make_temporary_folder(prefix)
        yield folder
    finally:
        if folder is not None:
            remove_temporary_folder(folder)
