"""The live loop and the `hoembed` command in the wheel: the scripted LiveSession run of
live_reference.py (points and the default, transformed, point normals) equals the VTK
build's (the same drivers: bit for bit in the test build whose stepper kernels are
compiled as the VTK build's, HOEMBED_PIP_NATIVE=1; to round-off in the portable wheel),
and the console script answers."""

import os
import shutil
import subprocess
import sys

import live_reference
import numpy as np
import pytest

REF = os.environ.get("HOEMBED_PIP_REFERENCE", "")
if not REF or not os.path.exists(os.path.join(REF, "live.npz")):
    pytest.skip("HOEMBED_PIP_REFERENCE (with live.npz) not given", allow_module_level=True)


# the stepper's kernels compiled as the VTK build's (the bitwise test build of
# scripts/test_pip.sh), else the portable wheel: its frames agree to round-off only (no FMA
# contraction), test_pip.py's ROUND_OFF of the run's size for the points, and the float32
# normals computed from them to a few float32 units
NATIVE = os.environ.get("HOEMBED_PIP_NATIVE") == "1"
ROUND_OFF = 1e-9
NORMALS_ROUND_OFF = 1e-5


def test_live_session_equals_the_vtk_build():
    ref = np.load(os.path.join(REF, "live.npz"))
    got = live_reference.run(REF)
    for key in ("positions", "surface", "normals", "time"):
        assert got[key].shape == ref[key].shape, key
        assert got[key].dtype == ref[key].dtype, key
        if NATIVE or key == "time":
            assert np.array_equal(got[key], ref[key]), key
            continue
        if key == "normals":
            tol = NORMALS_ROUND_OFF
        else:
            first = ref[key][0].reshape(-1, 3)
            tol = ROUND_OFF * np.linalg.norm(first.max(axis=0) - first.min(axis=0))
        err = np.abs(got[key].astype(np.float64) - ref[key]).max()
        assert err <= tol, (key, err, tol)
    # and it did move: the drag pulled the tip, the reset put it back
    moved = np.linalg.norm(got["positions"][-2] - got["positions"][0], axis=1).max()
    assert moved > 0.05
    assert np.array_equal(got["positions"][-1], got["positions"][0])
    assert got["time"][-1] == 0.0


@pytest.mark.parametrize("args", [["--help"], ["run", "--help"], ["live", "--help"]])
def test_console_script(args):
    exe = shutil.which("hoembed", path=os.path.dirname(sys.executable))
    assert exe, "the wheel's console script 'hoembed' is not installed"
    r = subprocess.run([exe] + args, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "usage: hoembed" in r.stdout
