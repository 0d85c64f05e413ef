"""Run every benchmark script in this folder (JSON results in Benchmarks/results/).

    make bench        # or: xvfb-run -a .venv/bin/python Benchmarks/run_all.py [names...]

Benchmarks never decide pass/fail; they measure (ratios against VTK's own filters where
there is one) and print JSON. Scripts that need ../shared/data/meshes skip without it.
Which script gives which figure of Benchmarks/RESULTS.md is said there, section by
section. The scripts in NOT_RUN are not run by default (the reason is printed); name one
to run it with its default options.
"""

import pathlib
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
SCRIPTS = [
    "bench_mesher",
    "bench_mesher_robust",
    "bench_mesher_real",
    "bench_embedding",
    "bench_embedding_exact",
    "bench_embedding_scale",
    "bench_transfer",
    "bench_transfer_shape",
    "bench_stepper",
    "bench_locking",
    "bench_shape_real",
    "bench_live",  # the rendered pass only under a display (xvfb-run, as above)
    "bench_pip",
]  # skips itself without the pip venv of `make test-pip`
NOT_RUN = {
    "bench_mpi": "needs `make paraview` and mpirun (2 processes, pvbatch); run it by name",
    "pv_bench_pieces": "run by bench_mpi under mpirun, not alone",
    "compare_builds": "compares two builds (dump with each, then compare): see its docstring",
    "compare_speed": "times two builds against each other (--a, --b): see its docstring",
    "thorny_beam": "helpers of the transfer benchmarks, not a benchmark",
}


def main(names):
    failed = []
    if not names:
        for name, why in NOT_RUN.items():
            print(f"== {name}: not run ({why})")
    for name in names or SCRIPTS:
        script = HERE / f"{name}.py"
        if not script.is_file():
            print(f"== {name}: not present, skipped")
            continue
        print(f"== {name}", flush=True)
        t0 = time.perf_counter()
        rc = subprocess.call([sys.executable, str(script)])
        print(f"== {name}: exit {rc}, {time.perf_counter() - t0:.0f} s", flush=True)
        if rc != 0:
            failed.append(name)
    if failed:
        print("failed:", " ".join(failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
