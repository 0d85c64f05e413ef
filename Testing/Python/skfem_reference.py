"""scikit-fem as the independent reference of the stepper's tests: its P1/P2 vector bases
on a VTK tet4/tet10 mesh, with the map VTK point -> its 3 DOFs built from skfem's vertex
and edge numbering (not from coordinates). Import after pytest.importorskip("skfem")."""
import numpy as np
import pyvista as pv
from skfem import Basis, BilinearForm, ElementTetP1, ElementTetP2, ElementVector, LinearForm
from skfem import MeshTet, MeshTet2, asm, condense, solve
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

VTK_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]  # VTK tet10 mid-node order


def vector_basis(mesh, order):
    """(basis, dofs): skfem's vector P`order` basis on the mesh (isoparametric P2 geometry
    with VTK's mid-node coordinates for order 2) and dofs[i] = the 3 DOFs of VTK point i."""
    ctype = pv.CellType.QUADRATIC_TETRA if order == 2 else pv.CellType.TETRA
    cells = mesh.cells_dict[ctype]
    corners = np.unique(cells[:, :4])
    assert corners.max() + 1 == len(corners)  # corner points come first in box_tet_mesh
    nv = len(corners)
    pts = np.asarray(mesh.points)
    sk = MeshTet(pts[:nv].T.copy(), cells[:, :4].T.copy())
    dofs = np.zeros((mesh.n_points, 3), dtype=int)
    if order == 2:
        edge_index = {tuple(sorted(e)): i for i, e in enumerate(sk.edges.T)}
        vtk_mid = np.full(sk.edges.shape[1], -1)
        for c in cells:
            for k, (a, b) in enumerate(VTK_EDGES):
                vtk_mid[edge_index[tuple(sorted((c[a], c[b])))]] = c[4 + k]
        assert (vtk_mid >= 0).all()
        sk2 = MeshTet2(np.hstack([pts[:nv].T, pts[vtk_mid].T]), cells[:, :4].T.copy())
        assert np.array_equal(sk2.edges, sk.edges)
        basis = Basis(sk2, ElementVector(ElementTetP2()), intorder=8)
        dofs[vtk_mid] = basis.edge_dofs.T
    else:
        basis = Basis(sk, ElementVector(ElementTetP1()))
    dofs[:nv] = basis.nodal_dofs.T
    return basis, dofs


def elasticity(basis, E, nu, rho, g=(0.0, 0.0, 0.0)):
    """(K, M, f): small-strain stiffness, consistent mass and body force rho * g."""
    @BilinearForm
    def mass(u, v, w):
        return rho * dot(u, v)

    @LinearForm
    def body(v, w):
        return rho * (g[0] * v[0] + g[1] * v[1] + g[2] * v[2])

    K = asm(linear_elasticity(*lame_parameters(E, nu)), basis)
    return K.tocsr(), asm(mass, basis).tocsr(), asm(body, basis)


def tip_pull(E, nu):
    """The prescribed-motion problem of the stepper's static tests: a (4, 2, 2) tet10 box
    of length 4, clamped at x = 0, its tip (x = 4) given a tiny prescribed displacement t.
    Returns (mesh, clamp, tip, t, ref): ref is linear elasticity with those inhomogeneous
    Dirichlet values (scikit-fem's condense with x), which the co-rotated equilibrium
    equals for so small a displacement."""
    from conftest import box_tet_mesh
    mesh = box_tet_mesh((4, 2, 2), (4.0, 1.0, 1.0), 2)
    pts = np.asarray(mesh.points)
    clamp = pts[:, 0] <= 1e-9
    tip = np.isclose(pts[:, 0], 4.0)
    t = np.zeros_like(pts)
    t[tip] = 1e-7 * np.c_[0.3 + 0 * pts[tip, 0], 1 + pts[tip, 2], -2 + pts[tip, 1]]
    basis, dofs = vector_basis(mesh, 2)
    K, _, _ = elasticity(basis, E, nu, 1000.0)
    x = np.zeros(K.shape[0])
    x[dofs[tip].ravel()] = t[tip].ravel()
    D = np.concatenate([dofs[clamp].ravel(), dofs[tip].ravel()])
    ref = solve(*condense(K, np.zeros(K.shape[0]), x=x, D=D))[dofs]
    return mesh, clamp, tip, t, ref
