"""2-process speed-up of the embedding + transfer in ParaView's distributed pipeline
(pvbatch under MPI, the HOEmbed plugin) against 1 process, in the same run.

A generated bumpy ellipsoid of >= 2M vertices is written as 2 pieces (surface.pvtp); the
pipeline (mesher -> embedding -> stepper -> transfer) runs under
`mpirun -np N scripts/pvbatch --mpi --symmetric Benchmarks/pv_bench_pieces.py` for N = 1
and 2, alternately (REPEATS times each), one SMP thread per process
(VTK_SMP_MAX_THREADS=1), so 2 processes use the 2 cores; the best time of each N is kept.
The mesher meshes the same shape at a coarse resolution (--mesh-fine: the fine surface,
gathered from the pieces; minutes at 2M vertices);
its time is not part of the measured embedding + transfer either way.
Besides the wall times (between barriers), each process reports its own wall and CPU time
(user + sys) of each timed part: the machine is shared, so the CPU times say what the
work is (the extra CPU time 2 processes spend together over 1 is the replicated work) and
CPU / wall says how much of a core each process got. --perf DIR records each process with
`perf record` over the timed parts only (perf report -i DIR/perf.N.REP.RANK --children).
JSON in Benchmarks/results/bench_mpi.json. Needs `make paraview`.

    xvfb-run -a .venv/bin/python Benchmarks/bench_mpi.py [--theta 2000 --phi 1002]
"""

import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT / "Plugin" / "Testing"))
from pv_surfaces import make_surface  # noqa: E402


def cpu_summary(runs):
    """What the processes' CPU times (user + sys) say, independent of the other load on
    the machine: the work of the timed parts per process, the extra work 2 processes do
    together over 1 (replicated or added by the split), the speed-up 2 free cores would
    give (the busier process against 1 process), and how much of its wall time each
    process had a core (CPU / wall: below 1, it waited for one)."""
    med = statistics.median
    work = {
        n: [[p["embedding_cpu_s"] + p["transfer_cpu_s"] for p in r["per_process"]] for r in v]
        for n, v in runs.items()
    }
    emb = {
        n: [[p["embedding_cpu_s"] for p in r["per_process"]] for r in v] for n, v in runs.items()
    }
    share = {
        n: [
            min(
                (p["embedding_cpu_s"] + p["transfer_cpu_s"])
                / (p["embedding_local_s"] + p["transfer_local_s"])
                for p in r["per_process"]
            )
            for r in v
        ]
        for n, v in runs.items()
    }
    one = med(w[0] for w in work[1])
    return {
        "cpu_1proc_embedding_plus_transfer_s_median": one,
        "cpu_2proc_per_process_s_median": [med(w[k] for w in work[2]) for k in range(2)],
        "cpu_2proc_extra_over_1proc_s_median": med(sum(w) for w in work[2]) - one,
        "cpu_2proc_extra_embedding_s_median": med(sum(w) for w in emb[2])
        - med(w[0] for w in emb[1]),
        "speedup_2proc_cpu_bound": one / med(max(w) for w in work[2]),
        "cpu_share_of_wall_min_process": {n: v for n, v in share.items()},
    }


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--theta", type=int, default=2000)
    p.add_argument("--phi", type=int, default=1002)  # 2000 * 1000 + 2 vertices
    p.add_argument("--frames", type=int, default=10)
    p.add_argument("--elements", type=int, default=1000)
    p.add_argument("--repeats", type=int, default=2)
    p.add_argument(
        "--perf",
        metavar="DIR",
        help="record each process with `perf record` (DWARF call graphs) into "
        "DIR/perf.N.REP.RANK "
        "(the timed parts only: the embedding and the transfer re-runs)",
    )
    p.add_argument(
        "--perf-parts",
        default="embedding,transfer",
        help="what --perf records: embedding, transfer, frame (the proxy's update "
        "of each frame: the stepper's step and the transfer), comma-separated",
    )
    p.add_argument(
        "--mesh-fine",
        action="store_true",
        help="mesh the fine surface itself (gathered; minutes at 2M vertices) "
        "instead of the same shape at 200 x 102",
    )
    args = p.parse_args()
    if not (ROOT / "build-paraview" / "build" / "lib" / "paraview-plugins" / "HOEmbed").is_dir():
        print("bench_mpi: the ParaView plugin is not built (make paraview); skipped")
        return 0
    runs = {1: [], 2: []}
    with tempfile.TemporaryDirectory() as tmp:
        _, pvtp = make_surface(tmp, npieces=2, theta=args.theta, phi=args.phi)
        coarse = None
        if not args.mesh_fine:
            coarse, _ = make_surface(pathlib.Path(tmp) / "coarse", npieces=1, theta=200, phi=102)
        env = dict(os.environ, VTK_SMP_MAX_THREADS="1", HOEMBED_PERF_PARTS=args.perf_parts)
        for rep in range(args.repeats):
            for n in (1, 2):
                out = pathlib.Path(tmp) / f"t{n}_{rep}.json"
                prefix = []
                if args.perf:
                    os.makedirs(args.perf, exist_ok=True)
                    # started paused (-D -1); pv_bench_pieces.py enables it over the timed
                    # parts only, through the control fifo named by HOEMBED_PERF_CTL
                    prefix = [
                        "sh",
                        "-c",
                        'f="$0.$OMPI_COMM_WORLD_RANK"; rm -f "$f.ctl" "$f.ack"; '
                        'mkfifo "$f.ctl" "$f.ack"; export HOEMBED_PERF_CTL="$f"; '
                        "exec perf record -q --call-graph dwarf,16384 -F 499 -D -1 "
                        '--control "fifo:$f.ctl,$f.ack" -o "$f" -- "$@"',
                        str(pathlib.Path(args.perf).resolve() / f"perf.{n}.{rep}"),
                    ]
                cmd = (
                    ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(n)]
                    + prefix
                    + [
                        str(ROOT / "scripts" / "pvbatch"),
                        "--mpi",
                        "--symmetric",
                        str(HERE / "pv_bench_pieces.py"),
                        str(pvtp),
                        str(out),
                        str(args.frames),
                        str(args.elements),
                    ]
                    + ([str(coarse)] if coarse else [])
                )
                load_before = os.getloadavg()
                r = subprocess.run(cmd, capture_output=True, text=True, env=env)
                if r.returncode != 0:
                    print(r.stdout[-2000:], r.stderr[-2000:])
                    return 1
                runs[n].append(
                    dict(
                        json.loads(out.read_text()),
                        load_avg_before=load_before,
                        load_avg_after=os.getloadavg(),
                    )
                )
                print(n, runs[n][-1], flush=True)
    best = {n: min(v, key=lambda x: x["embedding_plus_transfer_s"]) for n, v in runs.items()}
    result = {
        "surface_vertices": args.theta * (args.phi - 2) + 2,
        "frames": args.frames,
        "target_elements": args.elements,
        "threads_per_process": 1,
        "mesher_input": "the fine surface, gathered"
        if args.mesh_fine
        else "the same shape, 200 x 102",
        "runs": runs,
        "best": best,
        "speedup_2proc_embedding_plus_transfer": best[1]["embedding_plus_transfer_s"]
        / best[2]["embedding_plus_transfer_s"],
        "speedup_2proc_embedding": min(r["embedding_s"] for r in runs[1])
        / min(r["embedding_s"] for r in runs[2]),
        "speedup_2proc_transfer": min(r["transfer_s"] for r in runs[1])
        / min(r["transfer_s"] for r in runs[2]),
    }
    result.update(cpu_summary(runs))
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "bench_mpi.json").write_text(json.dumps(result, indent=1))
    print(json.dumps({k: v for k, v in result.items() if k != "runs"}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
