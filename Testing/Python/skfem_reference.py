"""scikit-fem as the independent reference of the stepper's tests: its P1/P2 vector bases
on a VTK tet4/tet10 mesh, with the map VTK point -> its 3 DOFs built from skfem's vertex
and edge numbering (not from coordinates). Import after pytest.importorskip("skfem")."""

import numpy as np
import pyvista as pv
from skfem import (
    Basis,
    BilinearForm,
    ElementTetP1,
    ElementTetP2,
    ElementVector,
    LinearForm,
    MeshTet,
    MeshTet2,
    asm,
    condense,
    solve,
)
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

VTK_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]  # VTK tet10 mid-node order


def vector_basis(mesh, order, quadrature=None):
    """(basis, dofs): skfem's vector P`order` basis on the mesh (isoparametric P2 geometry
    with VTK's mid-node coordinates for order 2) and dofs[i] = the 3 DOFs of VTK point i.
    `quadrature`: skfem's (points, weights) on the reference tet (default: intorder 8)."""
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
        basis = (
            Basis(sk2, ElementVector(ElementTetP2()), intorder=8)
            if quadrature is None
            else Basis(sk2, ElementVector(ElementTetP2()), quadrature=quadrature)
        )
        dofs[vtk_mid] = basis.edge_dofs.T
    else:
        basis = (
            Basis(sk, ElementVector(ElementTetP1()))
            if quadrature is None
            else Basis(sk, ElementVector(ElementTetP1()), quadrature=quadrature)
        )
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


# --- hyperelasticity ------------------------------------------------------------------
# The energy densities as the papers write them, in numpy (complex-safe: the stress is
# their complex-step derivative, the tangent a central difference of that stress; only
# Newton's convergence rate depends on the tangent, not the solution). F: (3, 3, ...).


def _det(F):
    return (
        F[0, 0] * (F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1])
        - F[0, 1] * (F[1, 0] * F[2, 2] - F[1, 2] * F[2, 0])
        + F[0, 2] * (F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0])
    )


def energy_density(material, E, nu, c10=0.0, c01=0.0):
    """Psi(F) of `material` with the conversions the stepper documents: StVK with Lame
    (lambda, mu); the stable Neo-Hookean of Smith, de Goes and Kim (2018), eq. 14 with
    mu' = 4/3 mu, lambda' = lambda + 5/6 mu; Mooney-Rivlin with deviatoric invariants,
    kappa = E / (3 (1 - 2 nu)), C10 = C01 = mu / 4 unless given."""
    lam, mu = lame_parameters(E, nu)

    def stvk(F):
        C = np.einsum("ki...,kj...->ij...", F, F)
        Eg = 0.5 * (C - np.eye(3).reshape((3, 3) + (1,) * (F.ndim - 2)))
        trE = Eg[0, 0] + Eg[1, 1] + Eg[2, 2]
        return mu * np.einsum("ij...,ij...->...", Eg, Eg) + 0.5 * lam * trE**2

    def neo_hookean(F):
        m, lm = 4.0 / 3.0 * mu, lam + 5.0 / 6.0 * mu
        alpha = 1.0 + 3.0 * m / (4.0 * lm)
        Ic = np.einsum("ij...,ij...->...", F, F)
        return 0.5 * m * (Ic - 3.0) + 0.5 * lm * (_det(F) - alpha) ** 2 - 0.5 * m * np.log(Ic + 1.0)

    def mooney_rivlin(F):
        a, b = (0.25 * mu, 0.25 * mu) if c10 == 0.0 and c01 == 0.0 else (c10, c01)
        kappa = E / (3.0 * (1.0 - 2.0 * nu))
        C = np.einsum("ki...,kj...->ij...", F, F)
        I1 = np.einsum("ij...,ij...->...", F, F)
        I2 = 0.5 * (I1**2 - np.einsum("ij...,ij...->...", C, C))
        J = _det(F)
        return (
            a * (J ** (-2.0 / 3.0) * I1 - 3.0)
            + b * (J ** (-4.0 / 3.0) * I2 - 3.0)
            + 0.5 * kappa * (J - 1.0) ** 2
        )

    return {"stvk": stvk, "neo-hookean": neo_hookean, "mooney-rivlin": mooney_rivlin}[material]


def _stress(psi, F):
    h = 1e-30
    P = np.zeros(F.shape)
    for k in range(3):
        for m in range(3):
            Fc = F.astype(complex)
            Fc[k, m] += 1j * h
            P[k, m] = np.imag(psi(Fc)) / h
    return P


def _tangent(psi, F):
    A = np.zeros((3, 3) + F.shape)
    eps = 1e-6
    for k in range(3):
        for m in range(3):
            Fp, Fm = F.copy(), F.copy()
            Fp[k, m] += eps
            Fm[k, m] -= eps
            A[:, :, k, m] = (_stress(psi, Fp) - _stress(psi, Fm)) / (2 * eps)
    return A


def hyper_rule(order):
    """The quadrature the stepper documents for its hyperelastic energy, as skfem's
    (points (3, n), weights) on the reference tet: tet10, the symmetric 4-point rule of
    degree 2 (barycentric (a, b, b, b), weights 1/24); tet4, the centroid."""
    if order == 1:
        return np.full((3, 1), 0.25), np.array([1.0 / 6.0])
    a, b = 0.58541019662496845446, 0.13819660112501051518
    pts = np.array([[b, b, b], [a, b, b], [b, a, b], [b, b, a]]).T.copy()
    return pts, np.full(4, 1.0 / 24.0)


def hyperelastic_dynamic(mesh, order, material, E, nu, rho, g, held, dt, steps, tol=1e-12):
    """Backward Euler without damping by scikit-fem: each step solves
    M (u - u_n - dt v_n) / dt^2 + f_int(u) = f (consistent mass, body force rho * g) by
    Newton, v = (u - u_n) / dt, the `held` points at rest. Returns the displacement per
    VTK point after each step."""
    from skfem import BilinearForm, LinearForm
    from skfem.helpers import ddot, grad

    basis, dofs = vector_basis(mesh, order, hyper_rule(order))
    psi = energy_density(material, E, nu)

    @LinearForm
    def internal(v, w):
        return ddot(w["P"], grad(v))

    @BilinearForm
    def stiffness(u, v, w):
        return np.einsum("ijkl...,kl...,ij...->...", w["A"], grad(u), grad(v))

    _, M, f = elasticity(vector_basis(mesh, order)[0], E, nu, rho, g)
    D = dofs[held].ravel()
    u, v = np.zeros(basis.N), np.zeros(basis.N)
    out = []
    for _ in range(steps):
        un = u.copy()
        for it in range(60):
            F = np.asarray(np.eye(3)[:, :, None, None] + grad(basis.interpolate(u)))
            r = M @ (u - un - dt * v) / dt**2 + asm(internal, basis, P=_stress(psi, F)) - f
            K = M / dt**2 + asm(stiffness, basis, A=_tangent(psi, F))
            du = solve(*condense(K, -r, D=D))
            u += du
            if np.abs(du).max() <= tol * max(np.abs(u - un).max(), 1e-300):
                break
        else:
            raise RuntimeError("scikit-fem Newton did not converge")
        v = (u - un) / dt
        out.append(u[dofs].copy())
    return out


def hyperelastic_static(mesh, order, material, E, nu, rho, g, held, targets, loads=8, tol=1e-12):
    """Static equilibrium of `material` by scikit-fem: P`order` on `mesh`, body force
    rho * g, the points `held` (mask) put on their displacements `targets` (n, 3), by
    Newton's method over `loads` equal load increments. Returns the displacement per VTK
    point."""
    from skfem import BilinearForm, LinearForm
    from skfem.helpers import ddot, grad

    basis, dofs = vector_basis(mesh, order, hyper_rule(order))
    psi = energy_density(material, E, nu)

    @LinearForm
    def internal(v, w):
        return ddot(w["P"], grad(v))

    @BilinearForm
    def stiffness(u, v, w):
        return np.einsum("ijkl...,kl...,ij...->...", w["A"], grad(u), grad(v))

    @LinearForm
    def body(v, w):
        return rho * (g[0] * v[0] + g[1] * v[1] + g[2] * v[2])

    # the load with skfem's default rule (the centroid does not integrate N_a of P2)
    f = asm(body, vector_basis(mesh, order)[0])
    D = dofs[held].ravel()
    u = np.zeros(basis.N)
    for step in range(1, loads + 1):
        s = step / loads
        u[D] = s * np.asarray(targets)[held].ravel()
        for it in range(60):
            F = np.eye(3)[:, :, None, None] + grad(basis.interpolate(u))
            F = np.asarray(F)
            r = asm(internal, basis, P=_stress(psi, F)) - s * f
            K = asm(stiffness, basis, A=_tangent(psi, F))
            du = solve(*condense(K, -r, D=D))
            u += du
            if np.abs(du).max() <= tol * max(np.abs(u).max(), 1e-300):
                break
        else:
            raise RuntimeError("scikit-fem Newton did not converge")
    return u[dofs]
