"""Make the repository importable as the package `lpv_preview` for the tests."""
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

try:
    import lpv_preview  # noqa: F401  (the set-up script links it into the virtual environment)
except ImportError:
    link_dir = tempfile.mkdtemp(prefix="lpv_preview_")
    os.symlink(ROOT, os.path.join(link_dir, "lpv_preview"))
    sys.path.insert(0, link_dir)

import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

# The property tests draw the same examples every run (CI is never flaky) and keep no
# example database in the repository, where the extension's builder would pack it.
settings.register_profile("lpv_preview", database=None, derandomize=True)
settings.load_profile("lpv_preview")


@pytest.fixture(scope="session")
def glc():
    """The real OpenGL 4.5 context (llvmpipe on CI) that the pipelines share too."""
    from lpv_preview.gpu.context import GLContext
    context = GLContext.shared()
    print(f"\nOpenGL renderer: {context.renderer} ({context.version})")
    return context
