"""The transfer's checks of what the embedded surface and the deformed mesh hold, in the
wheel against the VTK build: both run hoembed::TransferDriver's CheckMeshSize,
CheckSurface and FrameArraysUsed (the bindings only read the VTK objects), so each broken
case must fail with the VTK build's sentence, and each case whose odd arrays are not read
(or are read as missing) must give the VTK build's output bit for bit.
References: HOEMBED_PIP_REFERENCE/transfer_checks (transfer_checks_reference.py)."""

import json
import os

import hoembed
import numpy as np
import pytest
import pyvista
import transfer_checks_reference as tc

REF = os.environ.get("HOEMBED_PIP_REFERENCE", "")
FOLDER = os.path.join(REF, "transfer_checks")
if not REF or not os.path.exists(os.path.join(FOLDER, "errors.json")):
    pytest.skip(
        "HOEMBED_PIP_REFERENCE (generate_reference.py output with transfer_checks) not given",
        allow_module_level=True,
    )
ERRORS = json.load(open(os.path.join(FOLDER, "errors.json")))
KEYS = sorted(tc.cases(pyvista, REF))


def test_every_case_has_a_reference():
    # the broken ones failed in the VTK build, the others wrote an output
    for key in KEYS:
        assert (key in ERRORS) != os.path.exists(os.path.join(FOLDER, f"{key}.vtp")), key
    assert len(ERRORS) >= 10


@pytest.mark.parametrize("key", KEYS)
def test_same_as_the_vtk_build(key):
    surface, mesh, normals = tc.cases(pyvista, REF)[key]
    if key in ERRORS:
        with pytest.raises(hoembed.HOEmbedError) as info:
            hoembed.transfer(surface, mesh, normals=normals)
        assert tc.sentence(str(info.value)) == tc.sentence(ERRORS[key])
        assert str(info.value).startswith("transfer: ")
    else:
        got = hoembed.transfer(surface, mesh, normals=normals)
        ref = pyvista.read(os.path.join(FOLDER, f"{key}.vtp"))
        a, b = np.asarray(got.points), np.asarray(ref.points)
        assert a.dtype == b.dtype and np.array_equal(a.view(np.uint8), b.view(np.uint8))
