"""Bounded fuzz test: randomly damaged surfaces through the mesher and the embedding.

Fixed seeds, a few dozen cases (HOEMBED_FUZZ_CASES overrides the count). Each case ends
in one of two accepted outcomes:
- a clear error (HOEmbedError from the mesher or the embedding: today the mesher refuses
  open, non-manifold and self-intersecting surfaces), or
- success, and then: no NaN anywhere, every element valid (det J > 0 at its nodes and
  centroid, computed here from VTK's own quadratic-tetra shape-function derivatives, and
  VTK's vtkCellValidator finds no intersecting or flipped faces), every vertex embedded
  (a cell id in range), and every residual at most 1e-10 of the diagonal or flagged (a
  warning from the embedding or uncertified points).
A signal (crash), a hang, another exception, a NaN or an invalid element fails. The cases
run in a worker process that reports each one before starting it, so a crash names its
case.
"""

import json
import os
import signal
import subprocess
import sys

import numpy as np

N_CASES = int(os.environ.get("HOEMBED_FUZZ_CASES", "400"))

# Failures this test found whose fix is tracked elsewhere: reported in the output, not
# failed on (seed: why). Remove an entry when its fix lands; a failure of any other seed
# fails the test. None at present.
KNOWN = {}
DAMAGES = (
    "jitter",
    "spikes",
    "holes",
    "flips",
    "duplicate",
    "collapse",
    "overlap",
    "tiny",
    "huge",
    "nan",
    "shuffle",
    "dent",
)


def _base(rng):
    import pyvista as pv

    kind = rng.integers(3)
    if kind == 0:
        s = pv.Sphere(
            theta_resolution=int(rng.integers(12, 40)), phi_resolution=int(rng.integers(12, 40))
        )
    elif kind == 1:
        s = (
            pv.ParametricTorus(
                ringradius=1.0,
                crosssectionradius=0.35,
                u_res=int(rng.integers(20, 40)),
                v_res=int(rng.integers(12, 24)),
                w_res=0,
            )
            .triangulate()
            .clean()
        )
    else:
        s = pv.Box(level=int(rng.integers(2, 6)), quads=False).clean()
    return s.triangulate().clean()


def damaged_surface(seed):
    """A closed surface with one or two kinds of damage, chosen by the seed."""
    import pyvista as pv

    rng = np.random.default_rng(seed)
    s = _base(rng)
    pts = np.array(s.points, dtype=float)
    faces = s.faces.reshape(-1, 4)[:, 1:].copy()
    edge = s.length / np.sqrt(s.n_cells)
    kinds = list(rng.choice(DAMAGES, size=int(rng.integers(1, 3)), replace=False))
    for kind in kinds:
        if kind == "jitter":
            pts += rng.normal(scale=rng.uniform(0.01, 0.5) * edge, size=pts.shape)
        elif kind == "spikes":
            idx = rng.choice(len(pts), size=int(rng.integers(1, 6)), replace=False)
            pts[idx] *= rng.uniform(1.2, 3.0, size=(len(idx), 1))
        elif kind == "dent":
            idx = rng.choice(len(pts), size=int(rng.integers(1, 6)), replace=False)
            pts[idx] *= rng.uniform(-0.5, 0.5, size=(len(idx), 1))
        elif kind == "holes":
            keep = rng.random(len(faces)) > rng.uniform(0.001, 0.05)
            faces = faces[keep] if keep.any() else faces[:1]
        elif kind == "flips":
            idx = rng.choice(len(faces), size=int(rng.integers(1, 6)), replace=False)
            faces[idx] = faces[idx][:, ::-1]
        elif kind == "duplicate":
            idx = rng.choice(len(faces), size=int(rng.integers(1, 4)), replace=False)
            faces = np.vstack([faces, faces[idx]])
        elif kind == "collapse":
            for f in faces[rng.choice(len(faces), size=int(rng.integers(1, 6)), replace=False)]:
                pts[f[1]] = pts[f[0]]
        elif kind == "overlap":
            shift = rng.normal(size=3) * 0.3 * s.length
            faces = np.vstack([faces, faces + len(pts)])
            pts = np.vstack([pts, pts + shift])
        elif kind == "tiny":
            pts *= 1e-6
        elif kind == "huge":
            pts *= 1e6
        elif kind == "nan":
            pts[rng.integers(len(pts))] = np.nan
        elif kind == "shuffle":
            perm = rng.permutation(len(pts))
            inv = np.empty_like(perm)
            inv[perm] = np.arange(len(perm))
            pts = pts[perm]
            faces = inv[faces]
    cells = np.hstack([np.full((len(faces), 1), 3), faces]).ravel()
    return pv.PolyData(pts, cells), kinds


def _jacobian_dets(mesh):
    """det J of every tet10 at its 10 nodes and centroid, from VTK's shape-function
    derivatives (vtkQuadraticTetra.InterpolationDerivs)."""
    from vtkmodules.vtkCommonDataModel import vtkQuadraticTetra

    params = np.array(
        [
            [0, 0, 0],
            [1, 0, 0],
            [0, 1, 0],
            [0, 0, 1],
            [0.5, 0, 0],
            [0.5, 0.5, 0],
            [0, 0.5, 0],
            [0, 0, 0.5],
            [0.5, 0, 0.5],
            [0, 0.5, 0.5],
            [0.25, 0.25, 0.25],
        ]
    )
    dn = np.empty((len(params), 3, 10))
    for k, pc in enumerate(params):
        d = [0.0] * 30
        vtkQuadraticTetra.InterpolationDerivs(list(pc), d)
        dn[k] = np.array(d).reshape(3, 10)
    conn = mesh.cells.reshape(-1, 11)[:, 1:]
    x = mesh.points[conn]  # (cells, 10, 3)
    jac = np.einsum("kaj,cjd->ckad", dn, x)  # (cells, points, 3 params, 3 coords)
    return np.linalg.det(jac)


def _vtk_invalid_cells(mesh):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkFiltersGeneral import vtkCellValidator

    # vtkCellValidator's intersection tests use absolute tolerances: at the "tiny" scale
    # (diagonal 1e-6) it flags valid straight cells. Validity is scale-invariant, so the
    # mesh is checked scaled to a unit diagonal.
    unit = mesh.copy()
    unit.points = (unit.points - unit.center) / mesh.length
    v = vtkCellValidator()
    v.SetInputData(unit)
    v.SetTolerance(1e-6)
    v.Update()
    state = vtk_to_numpy(v.GetOutput().GetCellData().GetArray("ValidityState"))
    bad = 0
    for name in (
        "IntersectingEdges",
        "IntersectingFaces",
        "FacesAreOrientedIncorrectly",
        "WrongNumberOfPoints",
    ):
        bad |= int(getattr(vtkCellValidator, name))
    return int(np.count_nonzero(state & bad))


def run_case(seed):
    """One case; returns a dict (outcome "error" or "ok" with its checks). Raises on a
    failed check."""
    import hoembed
    from hoembed._errors import run_filter

    surface, kinds = damaged_surface(seed)
    rec = dict(seed=seed, damage=kinds)
    try:
        mesh = hoembed.tet10_mesh(surface, n_elements=150)
    except hoembed.HOEmbedError as err:
        assert str(err).strip(), "empty error message"
        rec.update(outcome="error", stage="mesh", message=str(err)[:200])
        return rec
    assert np.all(np.isfinite(mesh.points)), "NaN in the mesh"
    assert mesh.n_cells > 0 and np.all(mesh.celltypes == 24), "not all cells are tet10"
    dets = _jacobian_dets(mesh)
    assert np.all(dets > 0), f"{int(np.count_nonzero((dets <= 0).any(axis=1)))} invalid elements"
    assert _vtk_invalid_cells(mesh) == 0, "vtkCellValidator rejects elements"
    emb = hoembed.vtkEmbeddingCoordinatesFilter()
    emb.SetInputData(0, surface)
    emb.SetMeshData(mesh)
    warnings = []
    try:
        out = run_filter(emb, warnings=warnings)
    except hoembed.HOEmbedError as err:
        rec.update(outcome="error", stage="embed", message=str(err)[:200])
        return rec
    import pyvista as pv

    out = pv.wrap(out)
    cell = np.asarray(out.point_data["EmbeddingCellId"])
    assert cell.shape[0] == surface.n_points
    assert np.all((cell >= 0) & (cell < mesh.n_cells)), "a vertex is not embedded"
    for name in ("EmbeddingParametricCoords", "EmbeddingDistance", "EmbeddingResidual"):
        assert np.all(np.isfinite(out.point_data[name])), f"NaN in {name}"
    residual = np.asarray(out.point_data["EmbeddingResidual"])
    diag = surface.length
    unflagged_ok = bool(warnings) or emb.GetNumberOfUncertifiedPoints() > 0
    rec.update(
        outcome="ok",
        cells=int(mesh.n_cells),
        max_residual=float(residual.max() / diag),
        flagged=unflagged_ok,
    )
    assert residual.max() <= 1e-10 * diag or unflagged_ok, (
        f"residual {residual.max() / diag:.3g} of the diagonal, not flagged"
    )
    return rec


def _worker(first, count):
    """Run cases first..first+count-1, one JSON line before and after each."""
    for seed in range(first, first + count):
        print(json.dumps(dict(start=seed)), flush=True)
        try:
            rec = run_case(seed)
        except AssertionError as err:
            rec = dict(seed=seed, outcome="failed", message=str(err))
        except Exception as err:  # anything but a clear HOEmbedError
            rec = dict(seed=seed, outcome="failed", message=f"{type(err).__name__}: {err}")
        print(json.dumps(rec), flush=True)


def test_damaged_surfaces():
    here = os.path.dirname(os.path.abspath(__file__))
    code = (
        "import sys; sys.path.insert(0, sys.argv[1]); import test_fuzz_surfaces as t; "
        "t._worker(int(sys.argv[2]), int(sys.argv[3]))"
    )
    results, next_seed = [], 1000
    while next_seed < 1000 + N_CASES:
        r = subprocess.run(
            [sys.executable, "-c", code, here, str(next_seed), str(1000 + N_CASES - next_seed)],
            capture_output=True,
            encoding="utf-8",
            errors="replace",
            timeout=1800,
        )
        started = None
        for line in r.stdout.splitlines():
            if not line.startswith("{"):
                continue
            rec = json.loads(line)
            if "start" in rec:
                started = rec["start"]
            else:
                results.append(rec)
                started = None
        if r.returncode != 0:
            how = signal.Signals(-r.returncode).name if r.returncode < 0 else f"exit {r.returncode}"
            results.append(
                dict(
                    seed=started,
                    outcome="failed",
                    message=f"worker died ({how}): {r.stderr[-2000:]}",
                )
            )
            next_seed = (started if started is not None else next_seed) + 1
        else:
            next_seed = 1000 + N_CASES
    for r in results:
        if r["outcome"] == "failed" and r["seed"] in KNOWN:
            r.update(outcome="known", reason=KNOWN[r["seed"]])
    failed = [r for r in results if r["outcome"] == "failed"]
    ok = [r for r in results if r["outcome"] == "ok"]
    known = [r for r in results if r["outcome"] == "known"]
    print(
        json.dumps(
            dict(
                cases=len(results),
                ok=len(ok),
                known=len(known),
                errors=len(results) - len(ok) - len(failed) - len(known),
                failed=len(failed),
            )
        )
    )
    for r in results:
        print(json.dumps(r))
    assert not failed, "\n".join(json.dumps(r) for r in failed)
    assert len(results) == N_CASES
    # Both outcomes occur: the test exercises the success checks, not only the errors.
    assert ok and len(ok) < len(results)
