"""pytest set-up: import `sets` from the build tree and find the apps and the shared data.

ctest sets SETS_BINARY_DIR (the build folder) and PYTHONPATH; run by hand:
    PYTHONPATH=build/python /usr/bin/python3 -m pytest tests/python
"""

import os
import pathlib
import subprocess
import sys

import pytest

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]
BINARY_DIR = pathlib.Path(os.environ.get("SETS_BINARY_DIR", SOURCE_DIR / "build"))
if str(BINARY_DIR / "python") not in sys.path:
    sys.path.insert(0, str(BINARY_DIR / "python"))

os.environ.setdefault("MPLBACKEND", "Agg")


def shared_dir():
    """../shared next to the source tree unless SETS_SHARED_DIR says otherwise."""
    return pathlib.Path(os.environ.get("SETS_SHARED_DIR", SOURCE_DIR.parent / "shared"))


@pytest.fixture
def app():
    """Runs an app of the build tree: app("sets-lpv-pui", "--data", ...) -> CompletedProcess."""

    def run(name, *args, check=True):
        exe = BINARY_DIR / "apps" / name / name
        if not exe.exists():
            pytest.skip("%s is not built (SETS_BUILD_APPS=OFF?)" % exe)
        r = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError("%s exited %d:\n%s%s" % (name, r.returncode, r.stdout, r.stderr))
        return r

    return run


@pytest.fixture
def emps_dir():
    d = shared_dir() / "data" / "emps"
    if not d.is_dir():
        pytest.skip("no shared data at %s (set SETS_SHARED_DIR)" % d)
    return d
