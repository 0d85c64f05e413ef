"""hoembed.simulate / vtkCorotationalFEMStepper against scikit-fem and invariants."""

import hoembed
import numpy as np
import pytest
import pyvista as pv
from conftest import box_tet_mesh

skfem = pytest.importorskip("skfem")
from skfem import condense, solve  # noqa: E402
from skfem_reference import elasticity, tip_pull, vector_basis  # noqa: E402


def skfem_static(mesh, E, nu, rho, g, order):
    """Small-strain linear elasticity by scikit-fem (P2 or P1), clamped at x = 0, with the
    consistent body force rho * g; returned per VTK point."""
    basis, dofs = vector_basis(mesh, order)
    K, _, f = elasticity(basis, E, nu, rho, g)
    D = basis.get_dofs(lambda x: x[0] <= 1e-9).all()
    return solve(*condense(K, f, D=D))[dofs]


def _curve(p):
    return p + np.c_[0 * p[:, 0], 0.05 * np.sin(p[:, 0]), 0.03 * np.cos(2 * p[:, 1])]


@pytest.mark.parametrize("nu, curved", [(0.3, False), (0.49, False), (0.499, False), (0.49, True)])
def test_static_matches_skfem_p2(nu, curved):
    # small load: the co-rotated equilibrium equals linear elasticity up to O(|u| / L)
    E, rho, g = 1e13, 1000.0, (0.0, -3.0, -9.81)
    mesh = box_tet_mesh((4, 2, 2), (4.0, 1.0, 1.0), 2, mapping=_curve if curved else None)
    ref = skfem_static(mesh, E, nu, rho, g, 2)
    frames = hoembed.simulate(
        mesh,
        young=E,
        poisson=nu,
        density=rho,
        gravity=g,
        fixed={"plane": ((0, 0, 0), (1, 0, 0))},
        static=True,
    )
    u = frames[0].point_data["Displacement"]
    rel = np.linalg.norm(u - ref) / np.linalg.norm(ref)
    assert rel < 1e-7, rel  # |u| ~ 1e-7 L here: see the test below
    assert np.linalg.norm(ref) > 0


def test_static_difference_to_linear_is_the_corotation_term():
    # The co-rotated equilibrium is not linear elasticity's: the two differ by O(|u| / L)
    # (each element's rotated frame), so the relative difference to scikit-fem's linear P2
    # solve grows in proportion to the load. Ten times the load (E ten times smaller) gives
    # ten times the difference (to 1%, then 5% where round-off joins in); a difference from
    # anything else (quadrature, node order, a solver stopping early) would not scale so. Ten times less load leaves the
    # round-off of x - X (the state is stored as positions: a few ulps of |x| / |u|), and
    # a stiff bar whose displacement is 1e-9 of its size still converges, to that round-off.
    rho, nu, g = 1000.0, 0.3, (0.0, -3.0, -9.81)
    mesh = box_tet_mesh((4, 2, 2), (4.0, 1.0, 1.0), 2, mapping=_curve)
    rel = {}
    for E in (1e11, 1e12, 1e13, 1e14, 1e15):
        ref = skfem_static(mesh, E, nu, rho, g, 2)
        u = hoembed.simulate(
            mesh,
            young=E,
            poisson=nu,
            density=rho,
            gravity=g,
            fixed={"plane": ((0, 0, 0), (1, 0, 0))},
            static=True,
        )[0].point_data["Displacement"]
        rel[E] = np.linalg.norm(u - ref) / np.linalg.norm(ref)
    assert rel[1e11] / rel[1e12] == pytest.approx(10.0, rel=0.01), rel
    # (at E = 1e13 the round-off of x - X, ~1e-8 here, is a few % of the difference; the
    # sanitizer build, without -march=native, measured a ratio of 9.84)
    assert rel[1e12] / rel[1e13] == pytest.approx(10.0, rel=0.05), rel
    assert rel[1e14] < 1e-7, rel
    assert rel[1e15] < 1e-6, rel


def test_static_matches_skfem_p1_tet4():
    E, nu, rho, g = 1e13, 0.3, 1000.0, (0.0, 0.0, -9.81)
    mesh = box_tet_mesh((4, 2, 2), (4.0, 1.0, 1.0), 1)
    ref = skfem_static(mesh, E, nu, rho, g, 1)
    u = hoembed.simulate(
        mesh,
        young=E,
        poisson=nu,
        density=rho,
        gravity=g,
        fixed={"plane": ((0, 0, 0), (1, 0, 0))},
        static=True,
    )[0].point_data["Displacement"]
    assert np.linalg.norm(u - ref) / np.linalg.norm(ref) < 1e-6


def test_frames_time_and_arrays():
    mesh = box_tet_mesh((4, 1, 1), (4.0, 1.0, 1.0), 2)
    frames = hoembed.simulate(
        mesh, steps=10, dt=0.02, young=1e6, fixed={"plane": ((0, 0, 0), (1, 0, 0))}, every=5
    )
    assert [f.field_data["TimeValue"][0] for f in frames] == pytest.approx([0.0, 0.1, 0.2])
    last = frames[-1]
    assert last.n_points == mesh.n_points and last.n_cells == mesh.n_cells
    np.testing.assert_allclose(
        last.points - mesh.points, last.point_data["Displacement"], atol=1e-12
    )
    assert last.point_data["NodalRotation"].shape == (mesh.n_points, 9)
    R = last.point_data["NodalRotation"].reshape(-1, 3, 3)
    np.testing.assert_allclose(
        R @ R.transpose(0, 2, 1), np.broadcast_to(np.eye(3), R.shape), atol=1e-12
    )
    assert np.all(np.linalg.det(R) > 0.999)
    assert last.cell_data["VonMisesStress"].shape == (mesh.n_cells,)
    assert last.point_data["Displacement"][:, 2].min() < 0
    assert np.all(np.isfinite(last.point_data["Velocity"]))
    # clamped nodes did not move
    clamped = np.isclose(mesh.points[:, 0], 0.0)
    assert np.abs(last.point_data["Displacement"][clamped]).max() == 0.0


def test_clamp_mask_plane_box_agree():
    mesh = box_tet_mesh((4, 1, 1), (4.0, 1.0, 1.0), 2)
    mask = np.isclose(mesh.points[:, 0], 0.0)
    kw = dict(steps=5, dt=0.01, young=1e6)
    a = hoembed.simulate(mesh, fixed=mask, **kw)[-1].point_data["Displacement"]
    b = hoembed.simulate(mesh, fixed={"plane": ((0, 0, 0), (1, 0, 0))}, **kw)[-1]
    c = hoembed.simulate(mesh, fixed={"box": (-1, 0.0, -1, 2, -1, 2)}, **kw)[-1]
    m2 = mesh.copy()
    m2.point_data["Fixed"] = mask.astype(np.int32)
    d = hoembed.simulate(m2, **kw)[-1].point_data["Displacement"]
    np.testing.assert_allclose(a, b.point_data["Displacement"], atol=1e-14)
    np.testing.assert_allclose(a, c.point_data["Displacement"], atol=1e-14)
    np.testing.assert_allclose(a, d, atol=1e-14)


def test_rigid_rotation_no_stress_no_drift():
    mesh = box_tet_mesh((3, 2, 2), (3.0, 1.0, 1.0), 2)
    th = 2.0
    Q = np.array([[np.cos(th), -np.sin(th), 0], [np.sin(th), np.cos(th), 0], [0, 0, 1]])
    u0 = mesh.points @ Q.T - mesh.points
    frames = hoembed.simulate(
        mesh, steps=30, dt=0.01, young=1e6, gravity=(0, 0, 0), initial_displacement=u0, every=10
    )
    for f in frames:
        np.testing.assert_allclose(f.point_data["Displacement"], u0, atol=1e-9)
        assert f.cell_data["VonMisesStress"].max() < 1e-6
        np.testing.assert_allclose(
            f.point_data["NodalRotation"].reshape(-1, 3, 3),
            np.broadcast_to(Q, (mesh.n_points, 3, 3)),
            atol=1e-9,
        )


def test_progress_and_tet10_beats_tet4_locking():
    calls = []
    tips = {}
    for order in (1, 2):
        mesh = box_tet_mesh((8, 2, 2), (8.0, 1.0, 1.0), order)
        f = hoembed.simulate(
            mesh,
            young=1e9,
            poisson=0.49,
            static=True,
            fixed={"plane": ((0, 0, 0), (1, 0, 0))},
            progress=lambda i, n: calls.append((i, n)),
        )[0]
        tips[order] = -f.point_data["Displacement"][:, 2].min()
    assert calls == [(1, 1), (1, 1)]
    assert tips[2] > 1.5 * tips[1]


@pytest.mark.parametrize(
    "kwargs, needle",
    [
        (dict(poisson=0.5), "PoissonRatio"),
        (dict(poisson=-1.0), "PoissonRatio"),
        (dict(young=0.0), "YoungModulus"),
        (dict(density=0.0), "Density"),
        (dict(dt=0.0), "TimeStep"),
        (dict(dt=-1.0), "TimeStep"),
    ],
)
def test_bad_properties_raise(kwargs, needle):
    mesh = box_tet_mesh((2, 1, 1), (2.0, 1.0, 1.0), 2)
    with pytest.raises(hoembed.HOEmbedError, match=needle):
        hoembed.simulate(mesh, steps=2, **kwargs)


def test_bad_mesh_and_state_raise():
    mesh = box_tet_mesh((2, 1, 1), (2.0, 1.0, 1.0), 2)
    cells = mesh.cells.reshape(-1, 11).copy()
    cells[3, [2, 3]] = cells[3, [3, 2]]  # swap two corners of cell 3 (and their mids)
    cells[3, [5, 7]] = cells[3, [7, 5]]
    cells[3, [9, 10]] = cells[3, [10, 9]]
    bad = pv.UnstructuredGrid(cells.ravel(), mesh.celltypes, mesh.points, deep=True)
    with pytest.raises(hoembed.HOEmbedError, match="cell 3"):
        hoembed.simulate(bad, steps=1)
    hexa = pv.ImageData(dimensions=(3, 3, 3)).cast_to_unstructured_grid()
    with pytest.raises(hoembed.HOEmbedError, match="Unsupported cell"):
        hoembed.simulate(hexa, steps=1)
    with pytest.raises(hoembed.HOEmbedError, match="time step 1"):
        hoembed.simulate(
            mesh,
            steps=3,
            fixed={"plane": ((0, 0, 0), (1, 0, 0))},
            external_force=np.full((mesh.n_points, 3), 1e300),
        )
    with pytest.raises(hoembed.HOEmbedError, match="clamped"):
        hoembed.simulate(mesh, static=True)
    with pytest.raises(hoembed.HOEmbedError, match="FixedArrayName"):
        hoembed.simulate(mesh, steps=1, fixed="NoSuchArray")


def test_real_mesh_bunny_frames(data_dir, tmp_path):
    surf = pv.read(str(data_dir / "bunny_lowres.obj"))
    mesh = hoembed.tet10_mesh(surf, n_elements=90)
    ymin = mesh.bounds[2]
    frames = hoembed.simulate(
        mesh,
        steps=20,
        dt=0.01,
        young=5e4,
        gravity=(0, -9.81, 0),
        fixed={"plane": ((0, ymin + 0.01, 0), (0, 1, 0))},
        every=10,
    )
    last = frames[-1]
    u = last.point_data["Displacement"]
    assert np.all(np.isfinite(u))
    clamped = mesh.points[:, 1] <= ymin + 0.01
    assert clamped.any() and np.abs(u[clamped]).max() == 0.0
    assert u[~clamped, 1].mean() < 0  # sags under gravity
    assert np.abs(u).max() < 0.5 * (mesh.bounds[3] - mesh.bounds[2])
    R = last.point_data["NodalRotation"].reshape(-1, 3, 3)
    np.testing.assert_allclose(
        R @ R.transpose(0, 2, 1), np.broadcast_to(np.eye(3), R.shape), atol=1e-10
    )
    path = hoembed.write_series(frames, tmp_path, "bunny")
    reader = pv.get_reader(path)
    assert len(reader.time_values) == len(frames)


def test_static_matches_skfem_p2_large_system():
    # >= 6000 DOF: the preconditioner is CHOLMOD's factor copied into float node blocks
    E, nu, rho, g = 1e13, 0.49, 1000.0, (0.0, -3.0, -9.81)
    mesh = box_tet_mesh((10, 5, 4), (4.0, 1.0, 1.0), 2, mapping=_curve)
    assert 3 * mesh.n_points >= 6000
    ref = skfem_static(mesh, E, nu, rho, g, 2)
    u = hoembed.simulate(
        mesh,
        young=E,
        poisson=nu,
        density=rho,
        gravity=g,
        fixed={"plane": ((0, 0, 0), (1, 0, 0))},
        static=True,
    )[0].point_data["Displacement"]
    assert np.linalg.norm(u - ref) / np.linalg.norm(ref) < 1e-6


@pytest.mark.parametrize("n", [(4, 2, 2), (10, 5, 4)])  # small and large preconditioner
def test_dynamic_steps_match_skfem_backward_euler(n):
    # stiff material, tiny strains: the co-rotated step is the linear backward Euler step
    # (M (1 + dt a) + K (dt b + dt^2)) dv = dt (f - K u - a M v - (b + dt) K v) to O(|grad u|)
    from scipy.sparse.linalg import spsolve

    E, nu, rho, g, dt, a, b, steps = 1e12, 0.49, 1000.0, (0.0, -3.0, -9.81), 0.01, 0.1, 0.01, 4
    mesh = box_tet_mesh(n, (4.0, 1.0, 1.0), 2)
    basis, dofs = vector_basis(mesh, 2)
    K, M, f = elasticity(basis, E, nu, rho, g)
    D = basis.get_dofs(lambda x: x[0] <= 1e-9).all()
    free = np.setdiff1d(np.arange(K.shape[0]), D)
    A = ((1 + dt * a) * M + (dt * b + dt * dt) * K).tocsr()[free][:, free]
    u = np.zeros(K.shape[0])
    v = np.zeros(K.shape[0])
    for _ in range(steps):
        rhs = dt * (f - K @ u - a * (M @ v) - (b + dt) * (K @ v))
        v[free] += spsolve(A, rhs[free])
        u += dt * v
    ref = u[dofs]

    frames = hoembed.simulate(
        mesh,
        steps=steps,
        dt=dt,
        young=E,
        poisson=nu,
        density=rho,
        gravity=g,
        fixed={"plane": ((0, 0, 0), (1, 0, 0))},
        rayleigh_mass=a,
        rayleigh_stiffness=b,
        solver_tolerance=1e-12,
    )
    got = frames[-1].point_data["Displacement"]
    assert np.linalg.norm(ref) > 0
    assert np.linalg.norm(got - ref) / np.linalg.norm(ref) < 1e-6


def test_prescribed_static_matches_skfem_and_dynamic_reaches_targets():
    # simulate(prescribed=(mask, displacement)): static, a tiny prescribed displacement of
    # the tip is linear elasticity with inhomogeneous Dirichlet values (scikit-fem's
    # condense with x); dynamic, the tip lands on its target exactly, at the speed limit
    # when one is given, and the rest follows (the stepper itself: test_live_stepper.py)
    E, nu = 1e5, 0.45
    mesh, clamp, tip, t, ref = tip_pull(E, nu)
    pts = np.asarray(mesh.points)
    plane = {"plane": ((0, 0, 0), (1, 0, 0))}
    u = hoembed.simulate(
        mesh, young=E, poisson=nu, gravity=(0, 0, 0), fixed=plane, static=True, prescribed=(tip, t)
    )[0].point_data["Displacement"]
    assert np.array_equal(u[tip], (pts[tip] + t[tip]) - pts[tip])
    assert np.linalg.norm(u - ref) / np.linalg.norm(ref) < 1e-5

    lift = (0.0, 0.0, 0.3)  # one vector for every prescribed node
    dt, speed = 0.01, 5.0  # 0.05 per step: there after 6 steps
    frames = hoembed.simulate(
        mesh,
        steps=10,
        dt=dt,
        young=E,
        poisson=nu,
        gravity=(0, 0, 0),
        fixed=plane,
        prescribed=(tip, lift),
        prescribed_speed_limit=speed,
    )
    for k, f in enumerate(frames):
        z = f.point_data["Displacement"][tip, 2]
        np.testing.assert_allclose(z, min(0.3, k * speed * dt), rtol=0, atol=1e-12)
        assert np.abs(f.point_data["Displacement"][clamp]).max() == 0.0
    middle = np.isclose(pts[:, 0], 2.0)
    assert frames[-1].point_data["Displacement"][middle, 2].mean() > 1e-3  # pulled up
    # without a limit: on the target after the first step
    first = hoembed.simulate(
        mesh,
        steps=1,
        dt=dt,
        young=E,
        gravity=(0, 0, 0),
        fixed=plane,
        prescribed=(tip.astype(int), lift),
    )[-1]
    np.testing.assert_allclose(first.point_data["Displacement"][tip, 2], 0.3, rtol=0, atol=1e-12)


def test_bad_prescribed_raises():
    mesh = box_tet_mesh((2, 1, 1), (2.0, 1.0, 1.0), 2)
    n = mesh.n_points
    ones = np.ones(n)
    cases = [
        ((np.ones(3), (0, 0, 1)), 0.0, "entries"),
        ("tip", 0.0, r"\(mask, displacement\)"),
        ((None, (0, 0, 1)), 0.0, "prescribed mask"),
        ((["a"] * n, (0, 0, 1)), 0.0, "prescribed mask must be numbers"),
        ((np.full(n, np.nan), (0, 0, 1)), 0.0, "NaN"),
        ((ones, (0, 0, np.nan)), 0.0, "not finite"),
        ((ones, np.zeros((4, 3))), 0.0, "shape"),
        ((ones, (0, 0, 1)), -1.0, "prescribed_speed_limit"),
        (None, np.inf, "prescribed_speed_limit"),
        (None, "fast", "prescribed_speed_limit"),
    ]
    for prescribed, speed, needle in cases:
        with pytest.raises(hoembed.HOEmbedError, match=needle):
            hoembed.simulate(mesh, steps=1, prescribed=prescribed, prescribed_speed_limit=speed)


def test_new_input_mesh_of_another_size_rebuilds():
    # the stepper given another mesh (another node count) after a run: the same frames as
    # a fresh stepper (the solver's ordering and factors were kept from the first mesh
    # and read out of bounds: a segfault); also in LiveMode with a background
    # factorisation under way (a grab on the step before)
    from vtkmodules.util.numpy_support import numpy_to_vtk

    small = box_tet_mesh((4, 2, 2), (4.0, 1.0, 1.0), 2)
    large = box_tet_mesh((6, 2, 2), (4.0, 1.0, 1.0), 2)
    plane = {"plane": ((0, 0, 0), (1, 0, 0))}
    ref = hoembed.simulate(large, steps=5, dt=0.01, fixed=plane)[-1]
    s = hoembed.vtkCorotationalFEMStepper()
    s.SetUseClampPlane(True)
    s.SetClampPlaneOrigin(0, 0, 0)
    s.SetClampPlaneNormal(1, 0, 0)
    for mesh in (small, large):
        s.SetInputData(mesh)
        s.UpdateTimeStep(0.05)
    np.testing.assert_array_equal(pv.wrap(s.GetOutput()).points, ref.points)

    s.LiveModeOn()
    s.SetBackgroundFactorization(True)
    s.SetFactorizationLag(1000)  # the grab's factor is never taken: still being made
    for mesh in (small, large, small):
        s.SetInputData(mesh)
        assert s.Step(2)
        tip = np.isclose(np.asarray(mesh.points)[:, 0], 4.0).astype(np.uint8)
        assert s.SetPrescribedMotion(
            numpy_to_vtk(tip, deep=True), numpy_to_vtk(np.zeros((mesh.n_points, 3)), deep=True)
        )
        assert s.Step(1)
        assert s.SetPrescribedMotion(None, None)
    assert np.all(np.isfinite(pv.wrap(s.GetOutput()).points))
