"""hoembed.simulate(material=...) (the stepper's hyperelastic laws and Newton) against
scikit-fem's P1/P2 static solves of the same energies (skfem_reference.py): same mesh,
same space, same quadrature rule, same load; a cantilever under gravity at large
deflection and a block compressed by 30%."""
import numpy as np
import pytest

import hoembed
from conftest import box_tet_mesh

skfem = pytest.importorskip("skfem")
from skfem_reference import hyperelastic_static  # noqa: E402

MATERIALS = ("stvk", "neo-hookean", "mooney-rivlin")


def cantilever(order):
    mesh = box_tet_mesh((4, 1, 1), (4.0, 1.0, 1.0), order)
    pts = np.asarray(mesh.points)
    return mesh, pts[:, 0] <= 1e-9


def block(order):
    mesh = box_tet_mesh((2, 2, 2), (1.0, 1.0, 1.0), order)
    pts = np.asarray(mesh.points)
    return mesh, pts[:, 2] <= 1e-9, np.isclose(pts[:, 2], 1.0)


@pytest.mark.parametrize("order", [2, 1])
@pytest.mark.parametrize("material", MATERIALS)
def test_cantilever_gravity_matches_skfem(material, order):
    # tip deflection ~ 30% of the length (linear theory: 0.38 g for this beam)
    E, nu, rho, g = 1e6, 0.3, 1000.0, (0.0, 0.0, -3.0)
    mesh, clamp = cantilever(order)
    ref = hyperelastic_static(mesh, order, material, E, nu, rho, g, clamp,
                              np.zeros((mesh.n_points, 3)))
    u = hoembed.simulate(mesh, young=E, poisson=nu, density=rho, gravity=g,
                         fixed=clamp.astype(np.uint8), static=True,
                         material=material)[0].point_data["Displacement"]
    # large: tet10 bends ~30% of the length; the locking tet4 less than a third of that
    assert np.abs(ref[:, 2]).max() > (1.0 if order == 2 else 0.25)
    rel = np.linalg.norm(u - ref) / np.linalg.norm(ref)
    assert rel < 1e-6, rel


@pytest.mark.parametrize("order", [2, 1])
@pytest.mark.parametrize("material", MATERIALS)
def test_block_compression_matches_skfem(material, order):
    E, nu = 1e5, 0.3
    mesh, bottom, top = block(order)
    t = np.zeros((mesh.n_points, 3))
    t[top, 2] = -0.3
    held = bottom | top
    ref = hyperelastic_static(mesh, order, material, E, nu, 1000.0, (0.0, 0.0, 0.0), held, t)
    u = hoembed.simulate(mesh, young=E, poisson=nu, gravity=(0, 0, 0),
                         fixed=bottom.astype(np.uint8), static=True, material=material,
                         prescribed=(top, t))[0].point_data["Displacement"]
    assert np.abs(ref[~held]).max() > 0.01  # it bulges
    rel = np.linalg.norm(u - ref) / np.linalg.norm(ref)
    assert rel < 1e-6, rel
