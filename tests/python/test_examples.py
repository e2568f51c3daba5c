"""The scripts of examples/python run as a user runs them and say what they should."""

import os
import pathlib
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR, shared_dir

EXAMPLES = SOURCE_DIR / "examples" / "python"


def run(script, out):
    r = subprocess.run([sys.executable, str(EXAMPLES / script), "--out", str(out)], capture_output=True, text=True,
                       env=dict(os.environ, MPLBACKEND="Agg"), timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    return r.stdout


def assert_png(path):
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000


def test_pui_example(tmp_path):
    out = run("pui_example.py", tmp_path)
    assert "every end certified: True" in out
    assert out.count("inside: True") == 2
    assert_png(tmp_path / "pui_example.png")


def test_zonotope_reduction_example(tmp_path):
    out = run("zonotope_reduction.py", tmp_path)
    for method in ("girard", "combastel", "pca"):
        line = next(l for l in out.splitlines() if l.startswith(method))
        assert "4 generators" in line and line.endswith("contains the sampled points: True")
    assert_png(tmp_path / "zonotope_reduction.png")


def test_emps_diagnosis_example(tmp_path):
    if not (shared_dir() / "data" / "emps" / "nominal.json").exists():
        out = run("emps_diagnosis.py", tmp_path)
        assert out.startswith("skipped:")
        pytest.skip("no EMPS recordings: the example skips with a message (checked)")
    out = run("emps_diagnosis.py", tmp_path)
    assert "coulomb_friction: Fc" in out
    for name in ("signals_estimation", "signals_validation", "signature"):
        assert_png(tmp_path / ("emps_%s.png" % name))
