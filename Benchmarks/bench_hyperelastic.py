"""The stepper's hyperelastic laws against the co-rotated one.

1. Frame time at ~3000 tet10 (box beam 20 x 5 x 5 cubes x 6 = 3000 cells, 14.5k DOF,
   clamped at x = 0, gravity, E = 5e4, nu = 0.49; LiveMode, one request per frame of one
   step, 10 frames after 2 warm-up frames): co-rotated; Neo-Hookean with one Newton
   iteration per frame (MaxNewtonIterations 1) and converged (default controls). Times are
   wall seconds per frame, measured in the same run (the machine is shared: compare the
   ratios to the co-rotated frame).
2. Tip deflection of a cantilever (8 x 2 x 2 cubes, 4 x 1 x 1, tet10, E = 1e6, nu = 0.3,
   rho = 1000) under gravity g = s * 0.5 for s = 1, 2, 4, ..., 64, static: co-rotated
   (its static iteration may refuse large loads: then null) and each hyperelastic law,
   with the linear prediction; where they part.
Writes Benchmarks/results/bench_hyperelastic.json and bench_hyperelastic.png (the
deflections against g, and the frame times as ratios to the co-rotated frame of the same
run; `--plot` redraws it from the JSON).
"""

import json
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "Testing" / "Python"))

import hoembed  # noqa: E402
from conftest import box_tet_mesh  # noqa: E402


def frame_times(mesh, material, newton_iterations=None, frames=10):
    s = hoembed.vtkCorotationalFEMStepper()
    s.SetInputData(mesh)
    s.SetYoungModulus(5.0e4)
    s.SetPoissonRatio(0.49)
    s.SetGravity(0.0, 0.0, -9.81)
    s.SetUseClampPlane(True)
    s.SetClampPlaneOrigin(0.0, 0.0, 0.0)
    s.SetClampPlaneNormal(1.0, 0.0, 0.0)
    s.SetTimeStep(1.0 / 60.0)
    s.SetMaterial(material)
    if newton_iterations is not None:
        s.SetMaxNewtonIterations(newton_iterations)
    s.LiveModeOn()
    for _ in range(2):
        s.Step(1)
        s.Update()
    times, iterations = [], []
    for _ in range(frames):
        t0 = time.perf_counter()
        s.Step(1)
        s.Update()
        times.append(time.perf_counter() - t0)
        iterations.append(s.GetLastSolverIterations())
    tip = np.abs(np.asarray(s.GetOutput().GetPointData().GetArray("Displacement"))[:, 2]).max()
    return dict(
        ms_per_frame_median=1e3 * float(np.median(times)),
        ms_per_frame_mean=1e3 * float(np.mean(times)),
        iterations_per_frame=float(np.mean(iterations)),
        tip_after=float(tip),
    )


def deflections():
    mesh = box_tet_mesh((8, 2, 2), (4.0, 1.0, 1.0), 2)
    clamp = np.asarray(mesh.points)[:, 0] <= 1e-9
    E, nu, rho = 1e6, 0.3, 1000.0
    rows = []
    for s in (1, 2, 4, 8, 16, 32, 64):
        g = 0.5 * s
        row = dict(g=g, linear=None)
        for material in ("corotated", "stvk", "neo-hookean", "mooney-rivlin"):
            try:
                u = hoembed.simulate(
                    mesh,
                    young=E,
                    poisson=nu,
                    density=rho,
                    gravity=(0.0, 0.0, -g),
                    fixed=clamp.astype(np.uint8),
                    static=True,
                    material=material,
                )[0]
                row[material] = float(-u.point_data["Displacement"][:, 2].min())
            except hoembed.HOEmbedError:
                row[material] = None
        # linear elasticity = the co-rotated answer at a tiny load, scaled
        small = hoembed.simulate(
            mesh,
            young=E * 1e6,
            poisson=nu,
            density=rho,
            gravity=(0.0, 0.0, -g),
            fixed=clamp.astype(np.uint8),
            static=True,
        )[0]
        row["linear"] = 1e6 * float(-small.point_data["Displacement"][:, 2].min())
        rows.append(row)
        print(row, flush=True)
    return rows


def plot(out, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.2))
    rows = out["deflection"]
    g = [r["g"] for r in rows]
    for key, style in (
        ("linear", "k:"),
        ("corotated", "o-"),
        ("neo-hookean", "s-"),
        ("stvk", "^--"),
        ("mooney-rivlin", "v--"),
    ):
        pts = [(r["g"], r[key]) for r in rows if r.get(key) is not None]
        a.plot([p[0] for p in pts], [p[1] for p in pts], style, label=key)
    a.set_xscale("log", base=2)
    a.set_xlabel("gravity g (static)")
    a.set_ylabel("tip deflection (beam length 4)")
    a.set_title("4 x 1 x 1 cantilever, 192 tet10, E = 1e6, nu = 0.3")
    a.set_xticks(g)
    a.set_xticklabels([f"{x:g}" for x in g])
    a.grid(True, alpha=0.3)
    a.legend()
    frames = out["frames"]
    base = 0.5 * (
        frames["corotated"]["ms_per_frame_median"]
        + frames["corotated (again)"]["ms_per_frame_median"]
    )
    labels = ["corotated", "neo-hookean, 1 Newton iteration", "neo-hookean, converged"]
    ratios = [frames[k]["ms_per_frame_median"] / base for k in labels]
    b.bar(["co-rotated", "Neo-Hookean\n1 iteration", "Neo-Hookean\nconverged"], ratios)
    for i, r in enumerate(ratios):
        b.text(i, r, f"{r:.1f}x", ha="center", va="bottom")
    b.set_ylabel("frame time / co-rotated frame (same run)")
    b.set_title(f"LiveMode frame, {out['cells']} tet10 ({out['dof']} DOF)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    path = HERE / "results" / "bench_hyperelastic.json"
    if "--plot" in sys.argv:
        plot(json.loads(path.read_text()), path.with_suffix(".png"))
        return
    mesh = box_tet_mesh((20, 5, 5), (4.0, 1.0, 1.0), 2)
    out = dict(cells=mesh.n_cells, dof=3 * mesh.n_points, frames={})
    for label, material, it in (
        ("corotated", "corotated", None),
        ("neo-hookean, 1 Newton iteration", "neo-hookean", 1),
        ("neo-hookean, converged", "neo-hookean", None),
        ("corotated (again)", "corotated", None),
    ):
        out["frames"][label] = frame_times(mesh, material, it)
        print(label, out["frames"][label], flush=True)
    out["deflection"] = deflections()
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(out, indent=1))
    plot(out, path.with_suffix(".png"))


if __name__ == "__main__":
    main()
