"""Run every benchmark script in this folder (JSON results in Benchmarks/results/).

    make bench        # or: xvfb-run -a .venv/bin/python Benchmarks/run_all.py [names...]

Benchmarks never decide pass/fail; they measure (ratios against VTK's own filters where
there is one) and print JSON. Scripts that need ../shared/data/meshes skip without it.
"""
import pathlib
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
SCRIPTS = ["bench_mesher", "bench_embedding", "bench_embedding_exact", "bench_transfer",
           "bench_transfer_shape", "bench_stepper", "bench_locking", "bench_shape_real"]


def main(names):
    failed = []
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
