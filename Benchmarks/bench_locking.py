"""Volumetric locking (the paper's beam experiment, section 6.1).

A cantilever beam (8 x 1 x 1, clamped at x = 0) under gravity, nu = 0.49, small load
(static equilibrium of the co-rotated model == linear elasticity here). Tip deflection
(mean z displacement of the nodes on the tip face) for tet4 and tet10 box meshes of
increasing resolution against a converged reference (a fine tet10 solution); the error vs
DOF curves, and for each tet10 mesh the DOF a tet4 mesh needs for the same error
(interpolated in log-log on the tet4 curve; extrapolated with its last slope, and marked
so, when no tet4 mesh is that accurate). The paper reports up to 40x.
Writes Benchmarks/results/bench_locking.json and bench_locking.png.
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

L, H = 8.0, 1.0
E, NU, RHO = 1.0e9, 0.49, 1000.0


def tip_deflection(n, order):
    mesh = box_tet_mesh(n, (L, H, H), order)
    t0 = time.perf_counter()
    f = hoembed.simulate(
        mesh,
        young=E,
        poisson=NU,
        density=RHO,
        gravity=(0, 0, -9.81),
        fixed={"plane": ((0, 0, 0), (1, 0, 0))},
        static=True,
    )[0]
    dt = time.perf_counter() - t0
    tip = np.isclose(mesh.points[:, 0], L)
    return -float(f.point_data["Displacement"][tip, 2].mean()), 3 * mesh.n_points, dt


def dof_for_error(dofs, errs, target):
    """DOF at which the (log-log piecewise linear) curve reaches `target` error."""
    ld, le = np.log(dofs), np.log(errs)
    for i in range(len(dofs) - 1):
        if (le[i] - np.log(target)) * (le[i + 1] - np.log(target)) <= 0 and le[i] != le[i + 1]:
            s = (np.log(target) - le[i]) / (le[i + 1] - le[i])
            return float(np.exp(ld[i] + s * (ld[i + 1] - ld[i]))), False
    if target < errs[-1]:  # extrapolate with the last slope
        slope = (le[-1] - le[-2]) / (ld[-1] - ld[-2])
        if slope < 0:
            return float(np.exp(ld[-1] + (np.log(target) - le[-1]) / slope)), True
        return float("inf"), True
    return float(dofs[0]), True


def main():
    ref_n = (48, 6, 6)
    ref, ref_dof, ref_t = tip_deflection(ref_n, 2)
    check, check_dof, _ = tip_deflection((40, 5, 5), 2)
    inertia = H**4 / 12.0
    q = RHO * 9.81 * H * H
    beam_theory = q * L**4 / (8 * E * inertia)
    rows = {1: [], 2: []}
    series = {
        1: [(8, 1, 1), (16, 2, 2), (24, 3, 3), (32, 4, 4), (48, 6, 6), (64, 8, 8), (96, 12, 12)],
        2: [(4, 1, 1), (8, 1, 1), (8, 2, 2), (16, 2, 2), (24, 3, 3), (32, 4, 4)],
    }
    for order, meshes in series.items():
        for n in meshes:
            tip, dof, secs = tip_deflection(n, order)
            rows[order].append(
                {
                    "n": list(n),
                    "dof": dof,
                    "tip": tip,
                    "rel_error": abs(tip - ref) / ref,
                    "solve_s": secs,
                }
            )
    d4 = np.array([r["dof"] for r in rows[1]], float)
    e4 = np.array([r["rel_error"] for r in rows[1]], float)
    ratios = []
    for r in rows[2]:
        need, extrapolated = dof_for_error(d4, e4, r["rel_error"])
        r["tet4_dof_for_same_error"] = need
        r["tet4_dof_ratio"] = need / r["dof"]
        r["ratio_extrapolated"] = extrapolated
        ratios.append(r["tet4_dof_ratio"])
    interp = [r["tet4_dof_ratio"] for r in rows[2] if not r["ratio_extrapolated"]]
    result = {
        "benchmark": "bench_locking",
        "beam": {"length": L, "height": H, "young": E, "poisson": NU, "density": RHO},
        "reference": {
            "order": 2,
            "n": list(ref_n),
            "dof": ref_dof,
            "tip": ref,
            "solve_s": ref_t,
            "next_coarser_tet10_tip": check,
            "next_coarser_rel_diff": abs(check - ref) / ref,
            "euler_bernoulli_tip": beam_theory,
        },
        "tet4": rows[1],
        "tet10": rows[2],
        "max_tet4_dof_ratio_interpolated": max(interp) if interp else None,
        "max_tet4_dof_ratio_including_extrapolated": max(ratios),
    }
    out = HERE / "results"
    out.mkdir(exist_ok=True)
    (out / "bench_locking.json").write_text(json.dumps(result, indent=2))
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 4.5))
        for order, lab, mk in ((1, "tet4", "o-"), (2, "tet10", "s-")):
            ax.loglog(
                [r["dof"] for r in rows[order]],
                [r["rel_error"] for r in rows[order]],
                mk,
                label=lab,
            )
        ax.set_xlabel("degrees of freedom")
        ax.set_ylabel("relative tip-deflection error")
        ax.set_title(f"Cantilever under gravity, nu = {NU}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(out / "bench_locking.png", dpi=120)
        result["plot"] = str(out / "bench_locking.png")
    except Exception as exc:  # plotting is optional
        result["plot_error"] = repr(exc)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
