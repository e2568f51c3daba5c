"""Shared by the example scripts: command line (--out, --show) and finding `sets`."""

import argparse
import os
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def setup(description):
    """Parses --out DIR (where figures go, default: the current folder) and --show (open a
    window). Makes `import sets` work from a build tree (build/python) when not installed."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--out", default=".", help="folder for the figures (PNG)")
    parser.add_argument("--show", action="store_true", help="show the figures in a window")
    args = parser.parse_args()
    try:
        import sets  # noqa: F401
    except ImportError:
        build = pathlib.Path(os.environ.get("SETS_BINARY_DIR", ROOT / "build")) / "python"
        sys.path.insert(0, str(build))
    if not args.show:
        import matplotlib
        matplotlib.use("Agg")
    pathlib.Path(args.out).mkdir(parents=True, exist_ok=True)
    return args


def shared_dir():
    """../shared next to the source tree unless SETS_SHARED_DIR says otherwise."""
    return pathlib.Path(os.environ.get("SETS_SHARED_DIR", ROOT.parent / "shared"))
