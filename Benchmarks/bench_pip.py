"""The pip package's mesher, embed, transfer and simulate against the VTK build's, in
the same run.

    .venv/bin/python Benchmarks/bench_pip.py [--pip-python PATH] [--rounds N] [--reps N]
                                             [--mesh-reps N]

All are the pyvista-level functions (hoembed.tet10_mesh, hoembed.embed, hoembed.transfer,
hoembed.simulate) on the same inputs: the VTK build's run vtkTet10Mesher /
vtkEmbeddingCoordinatesFilter / vtkDeformationTransferFilter / vtkCorotationalFEMStepper
(Debian VTK 9.1, vtkSMPTools), the pip package's run the same drivers through nanobind
(pip VTK, std::thread loops; the mesher's VTK services called from Python). For the
wheel's mesher the calls of each service and the time spent in them (Python and pip VTK
together) are counted too ("services"). simulate: SIM_STEPS steps of the co-rotated
stepper on the same mesh, clamped at one end by a plane, under gravity, a frame every
SIM_EVERY steps (the set-up and factorisation included, as a user's call has them).
Each is timed in its own Python (the two VTKs cannot share
a process): children alternate, round after round, each timing `reps` calls; inputs
are written once by the VTK build. Wall-clock and process CPU time (all threads) per
call, median and minimum over all calls; the ratios pip / VTK are what to read (this
machine is shared). Needs the pip venv of `make test-pip` (build-pip/venv-py311-vtk942-pv0465, which holds
the bitwise test build: -march=native and CHOLMOD, as the VTK build).
Inputs: the thorny tail (46k vertices, and 102k) with ~1000 tet10, and armadillo.obj from
../shared/data/meshes when present. Writes Benchmarks/results/bench_pip.json; the JSON
is also the last line printed.
"""

import argparse
import hashlib
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
RESULTS = HERE / "results"
SIM_STEPS, SIM_EVERY = 20, 5
DATA = pathlib.Path(os.environ.get("HOEMBED_DATA_DIR", ROOT.parent / "shared" / "data" / "meshes"))


MESH_ELEMENTS = 1000


def timed_services():
    """Wrap the wheel's mesher services so that each call's time is summed (the wheel's
    _VTKServices counts the calls)."""
    from hoembed import meshing

    spent = {}
    names = (
        "ear_cut",
        "merge",
        "decimate",
        "closest",
        "ray",
        "vertices_within",
        "normal_at",
        "max_distance",
        "check_cell",
    )

    def wrap(name, f):
        def timed_call(*args):
            t0 = time.perf_counter()
            try:
                return f(*args)
            finally:
                spent[name] = spent.get(name, 0.0) + time.perf_counter() - t0

        return timed_call

    class Timed(meshing._VTKServices):
        pass

    for name in names:
        setattr(Timed, name, wrap(name, getattr(meshing._VTKServices, name)))
    meshing._VTKServices = Timed
    return spent


def service_profile(surface, spent):
    """One wheel mesher run: calls and seconds per service (`spent`: timed_services()'s,
    emptied here), and the run's wall time."""
    from hoembed import meshing
    from hoembed._checks import mesh_arguments

    spent.clear()
    options = mesh_arguments(surface, MESH_ELEMENTS, 0.0, 2, True, 1.5, 10.0, None, 0.2, 0.05)
    t0 = time.perf_counter()
    r, services = meshing._run(surface, options)
    total = time.perf_counter() - t0
    return {
        "wall_s": total,
        "cells": int(r["connectivity"].shape[0]),
        "calls": dict(services.calls),
        "seconds": dict(spent),
        "services_s": sum(spent.values()),
    }


def child(folder, reps, mesh_reps):
    """Time hoembed.tet10_mesh, hoembed.embed and hoembed.transfer (whichever hoembed
    this Python imports)."""
    import hoembed
    import numpy as np
    import pyvista

    out = {"backend": getattr(hoembed, "BACKEND", "vtk"), "cases": {}}
    for case in sorted(p.name for p in pathlib.Path(folder).iterdir() if p.is_dir()):
        d = pathlib.Path(folder) / case
        surface = pyvista.read(d / "surface.vtp")
        mesh = pyvista.read(d / "mesh.vtu")
        deformed = pyvista.read(d / "deformed.vtu")
        res = {}
        if mesh_reps > 0:
            res["mesh"] = timed(
                lambda: hoembed.tet10_mesh(surface, n_elements=MESH_ELEMENTS), mesh_reps, warm=False
            )
            res["mesh_cells"] = (
                int(hoembed.tet10_mesh(surface, n_elements=MESH_ELEMENTS).n_cells)
                if out["backend"] == "pip"
                else int(mesh.n_cells)
            )
        for name, call in (("embed", lambda: hoembed.embed(surface, mesh)),):
            res[name] = timed(call, reps)
        embedded = hoembed.embed(surface, mesh)
        res["transfer"] = timed(lambda: hoembed.transfer(embedded, deformed), reps)
        # a hash of the bytes: a float32 sum's rounding depends on numpy's version and
        # SIMD (the two Pythons have different numpys)
        x = np.ascontiguousarray(hoembed.transfer(embedded, deformed).points)
        res["transfer_checksum"] = hashlib.sha256(x.tobytes()).hexdigest()
        sim = simulate_kwargs(mesh)
        res["simulate"] = timed(lambda: hoembed.simulate(mesh, **sim), reps)
        u = np.ascontiguousarray(hoembed.simulate(mesh, **sim)[-1].point_data["Displacement"])
        res["simulate_checksum"] = hashlib.sha256(u.tobytes()).hexdigest()
        out["cases"][case] = res
    print(json.dumps(out))


def simulate_kwargs(mesh):
    """simulate()'s arguments: a soft body clamped near one end of its longest extent."""
    import numpy as np

    X = np.asarray(mesh.points, float)
    lo, hi = X.min(axis=0), X.max(axis=0)
    ax = int(np.argmax(hi - lo))
    origin = [float(lo[i] + 0.15 * (hi[i] - lo[i])) if i == ax else 0.0 for i in range(3)]
    normal = [float(i == ax) for i in range(3)]
    return dict(
        steps=SIM_STEPS,
        every=SIM_EVERY,
        dt=0.01,
        young=3e4,
        poisson=0.45,
        fixed={"plane": [origin, normal]},
    )


def timed(call, reps, warm=True):
    if warm:
        call()  # warm-up (page faults, first imports)
    wall, cpu = [], []
    for _ in range(reps):
        c0, t0 = time.process_time(), time.perf_counter()
        call()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return {"wall": wall, "cpu": cpu}


def make_inputs(folder):
    import hoembed
    import numpy as np
    import pyvista

    inputs = [
        ("thorny_tail", hoembed.thorny_tail()),
        # ~100k vertices: the mesher's service calls at that size
        ("thorny_tail_100k", hoembed.thorny_tail(rings=800, sectors=128)),
    ]
    if (DATA / "armadillo.obj").exists():
        inputs.append(("armadillo", pyvista.read(DATA / "armadillo.obj")))
    sizes = {}
    for name, surface in inputs:
        d = pathlib.Path(folder) / name
        d.mkdir(parents=True)
        mesh = hoembed.tet10_mesh(surface, n_elements=MESH_ELEMENTS)
        X = np.asarray(mesh.points, float)
        deformed = mesh.copy()
        # a bend (not rigid): the normals change with it
        s = (X[:, 0] - X[:, 0].min()) / np.ptp(X[:, 0])
        deformed.points = X + np.c_[0 * s, 0 * s, 0.2 * np.ptp(X[:, 0]) * s**2]
        surface.save(d / "surface.vtp")
        mesh.save(d / "mesh.vtu")
        deformed.save(d / "deformed.vtu")
        sizes[name] = {"surface_points": surface.n_points, "mesh_cells": mesh.n_cells}
    return sizes


def summary(values):
    import numpy as np

    v = np.asarray(values) * 1e3
    return {"median_ms": float(np.median(v)), "min_ms": float(v.min()), "n": len(v)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument(
        "--pip-python",
        default=str(ROOT / "build-pip" / "venv-py311-vtk942-pv0465" / "bin" / "python"),
    )
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument(
        "--mesh-reps",
        type=int,
        default=1,
        help="mesher calls per child and round (0: no mesher timing)",
    )
    ap.add_argument("--child", nargs=3, metavar=("FOLDER", "REPS", "MESH_REPS"))
    ap.add_argument("--profile", metavar="FOLDER", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(args.child[0], int(args.child[1]), int(args.child[2]))
        return 0
    if args.profile:
        import pyvista

        spent = timed_services()
        print(
            json.dumps(
                {
                    case.name: service_profile(pyvista.read(case / "surface.vtp"), spent)
                    for case in sorted(pathlib.Path(args.profile).iterdir())
                    if case.is_dir()
                }
            )
        )
        return 0
    if not os.path.exists(args.pip_python):
        # like the scripts that need ../shared/data: skipped, not failed
        print(f"no pip venv at {args.pip_python}: run `make test-pip` first (skipped)")
        return 0
    pythons = {"vtk": sys.executable, "pip": args.pip_python}
    with tempfile.TemporaryDirectory() as folder:
        sizes = make_inputs(folder)
        runs = {k: [] for k in pythons}
        for _ in range(args.rounds):
            for label, py in pythons.items():
                r = subprocess.run(
                    [py, __file__, "--child", folder, str(args.reps), str(args.mesh_reps)],
                    capture_output=True,
                    text=True,
                    check=True,
                    env=dict(os.environ, PYTHONWARNINGS="ignore"),
                )
                runs[label].append(json.loads(r.stdout.strip().splitlines()[-1]))
        profile = {}
        if args.mesh_reps > 0:
            r = subprocess.run(
                [args.pip_python, __file__, "--profile", folder],
                capture_output=True,
                text=True,
                check=True,
                env=dict(os.environ, PYTHONWARNINGS="ignore"),
            )
            profile = json.loads(r.stdout.strip().splitlines()[-1])
    result = {
        "benchmark": "bench_pip",
        "threads": os.cpu_count(),
        "rounds": args.rounds,
        "reps": args.reps,
        "mesh_reps": args.mesh_reps,
        "mesh_elements": MESH_ELEMENTS,
        "simulate": {"steps": SIM_STEPS, "every": SIM_EVERY},
        "cases": {},
    }
    ops = (("mesh",) if args.mesh_reps > 0 else ()) + ("embed", "transfer", "simulate")
    for case, size in sizes.items():
        entry = dict(size)
        if args.mesh_reps > 0:
            entry["mesh_cells"] = {
                label: runs[label][0]["cases"][case]["mesh_cells"] for label in pythons
            }
            entry["pip_mesher_services"] = profile.get(case)
        for op in ops:
            per = {}
            for label in pythons:
                wall = [t for run in runs[label] for t in run["cases"][case][op]["wall"]]
                cpu = [t for run in runs[label] for t in run["cases"][case][op]["cpu"]]
                per[label] = {"wall": summary(wall), "cpu": summary(cpu)}
            per["ratio_pip_over_vtk"] = {
                f"{kind}_{stat}": per["pip"][kind][stat] / per["vtk"][kind][stat]
                for kind in ("wall", "cpu")
                for stat in ("median_ms", "min_ms")
            }
            entry[op] = per
        checks = {label: runs[label][0]["cases"][case]["transfer_checksum"] for label in pythons}
        entry["same_transfer_output"] = checks["vtk"] == checks["pip"]
        checks = {label: runs[label][0]["cases"][case]["simulate_checksum"] for label in pythons}
        entry["same_simulate_output"] = checks["vtk"] == checks["pip"]
        result["cases"][case] = entry
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "bench_pip.json").write_text(json.dumps(result, indent=1))
    for case, e in result["cases"].items():
        for op in ops:
            r = e[op]["ratio_pip_over_vtk"]
            print(
                f"{case:12s} {op:8s} vtk {e[op]['vtk']['wall']['median_ms']:8.1f} ms  "
                f"pip {e[op]['pip']['wall']['median_ms']:8.1f} ms  ratio wall "
                f"{r['wall_median_ms']:.3f} (min {r['wall_min_ms']:.3f})  cpu "
                f"{r['cpu_median_ms']:.3f} (min {r['cpu_min_ms']:.3f})"
            )
        p = e.get("pip_mesher_services")
        if p:
            print(
                f"{case:12s} wheel mesher: {p['wall_s']:.2f} s, services "
                f"{p['services_s']:.2f} s in {sum(p['calls'].values())} calls "
                + ", ".join(
                    f"{k} {p['calls'][k]} ({p['seconds'].get(k, 0):.2f} s)"
                    for k in sorted(p["calls"])
                )
            )
    print(json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
