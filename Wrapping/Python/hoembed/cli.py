"""The ``hoembed`` command: the whole pipeline on a surface file or the built-in model.

    hoembed demo [--output output]          # built-in thorny tail, defaults below
    hoembed run SURFACE [options]           # any surface file VTK/pyvista reads
    hoembed live [SURFACE]                  # interactive: drag the surface (hoembed.live)

Pipeline: fine surface -> tet10 mesh (vtkTet10Mesher) -> embedding coordinates
(vtkEmbeddingCoordinatesFilter) -> co-rotated FE simulation under gravity with a clamped
region (vtkCorotationalFEMStepper) -> deformed fine surface per frame
(vtkDeformationTransferFilter) -> .pvd time series of the FE mesh and of the surface,
plus a picture comparing tet4 + barycentric with tet10 + normal-offset on the last frame.
"""

import argparse
import json
import math
import os
import pathlib
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time

import numpy as np

from ._arrays import N
from ._checks import NORMAL_MODE_NAMES, NORMAL_MODES
from ._hoembed import DEFAULTS, check_range

# the drivers' defaults (as the functions' and the filters'), where the commands take them
_MESHER, _STEPPER, _TRANSFER = DEFAULTS["mesher"], DEFAULTS["stepper"], DEFAULTS["transfer"]

EPILOG = """examples:
  hoembed demo
  hoembed run bunny.obj --elements 1500 --clamp-axis z --clamp-side min --steps 40
  hoembed run part.stl --young 2e5 --poisson 0.45 --gravity 0 -9.81 0 --output out

Open the results in ParaView (File > Open > OUTPUT/surface.pvd and OUTPUT/fe_mesh.pvd)
or in Python: pyvista.read("OUTPUT/surface.pvd").
"""


class UsageError(Exception):
    """A bad option or input file, reported without a traceback."""


def _parser():
    p = argparse.ArgumentParser(
        prog="hoembed",
        description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=EPILOG,
    )
    sub = p.add_subparsers(dest="command", required=True)
    demo = sub.add_parser(
        "demo",
        help="run the pipeline on the built-in thorny tail",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    run = sub.add_parser(
        "run",
        help="run the pipeline on a surface file",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    run.add_argument("surface", help="closed triangle surface (.obj .stl .ply .off .vtp .vtk ...)")
    live = sub.add_parser(
        "live",
        help="interactive window: drag the surface and it follows (hoembed.live)",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    live.add_argument(
        "surface", nargs="?", default=None, help="surface file (default: the built-in thorny tail)"
    )
    live.add_argument(
        "--elements",
        type=int,
        default=_MESHER["TargetNumberOfElements"],
        help="target number of tet10",
    )
    live.add_argument("--young", type=float, default=2e5, help="Young's modulus E (Pa)")
    live.add_argument(
        "--material",
        default=None,
        help="corotated, stvk, neo-hookean or mooney-rivlin (default: the stepper's, "
        "corotated); the hyperelastic laws take one Newton iteration per frame",
    )
    live.add_argument(
        "--gravity",
        type=float,
        nargs=3,
        default=(0.0, 0.0, 0.0),
        metavar=("GX", "GY", "GZ"),
        help="gravity (m/s^2)",
    )
    # the commands' own run (40 steps of 0.02 s; the demo's model stiffer), otherwise the
    # drivers' defaults
    gravity, elements = _STEPPER["Gravity"], _MESHER["TargetNumberOfElements"]
    for sp, defaults in (
        (demo, dict(steps=40, dt=0.02, young=1e7, gravity=gravity, elements=elements)),
        (
            run,
            dict(
                steps=40,
                dt=0.02,
                young=_STEPPER["YoungModulus"],
                gravity=gravity,
                elements=elements,
            ),
        ),
    ):
        sp.add_argument("--output", default="output", help="output folder")
        sp.add_argument(
            "--elements",
            type=int,
            default=defaults["elements"],
            help="target number of tet10 elements",
        )
        sp.add_argument(
            "--young", type=float, default=defaults["young"], help="Young's modulus E (Pa)"
        )
        sp.add_argument(
            "--poisson", type=float, default=_STEPPER["PoissonRatio"], help="Poisson's ratio"
        )
        sp.add_argument(
            "--density", type=float, default=_STEPPER["Density"], help="density (kg/m^3)"
        )
        sp.add_argument(
            "--material",
            default=None,
            help="corotated, stvk, neo-hookean or mooney-rivlin (default: the "
            "stepper's, corotated)",
        )
        sp.add_argument(
            "--gravity",
            type=float,
            nargs=3,
            default=defaults["gravity"],
            metavar=("GX", "GY", "GZ"),
            help="gravity (m/s^2)",
        )
        sp.add_argument("--steps", type=int, default=defaults["steps"], help="time steps")
        sp.add_argument("--dt", type=float, default=defaults["dt"], help="time step (s)")
        sp.add_argument(
            "--clamp-axis",
            choices="xyz",
            default=None,
            help="clamp the nodes at one end along this axis (with --clamp-side)",
        )
        sp.add_argument("--clamp-side", choices=("min", "max"), default="min")
        sp.add_argument(
            "--clamp-fraction",
            type=float,
            default=0.1,
            help="thickness of the clamped end, as a fraction of the extent",
        )
        sp.add_argument(
            "--clamp-sphere",
            type=float,
            nargs=4,
            default=None,
            metavar=("X", "Y", "Z", "R"),
            help="clamp the nodes inside a sphere",
        )
        sp.add_argument(
            "--normals",
            choices=tuple(NORMAL_MODES),
            default=NORMAL_MODE_NAMES[_TRANSFER["NormalMode"]],
            help="deformed normal field of the transfer: recompute (the paper's "
            "smooth normals of the deformed boundary, default), rotate "
            "(rest normals rotated by the nodal rotations) or deform (rest "
            "normals pushed forward by the nodal deformation gradient: "
            "surface detail leans with a shear of the surface)",
        )
        sp.add_argument("--no-picture", action="store_true", help="skip the comparison picture")
        sp.add_argument(
            "--no-tet4",
            action="store_true",
            help="skip the tet4 + barycentric baseline (and the picture)",
        )
    return p


class _Progress:
    """A one-line progress bar on stderr (tqdm when available)."""

    def __init__(self, label):
        self.label = label
        try:
            from tqdm import tqdm

            self.bar = tqdm(
                total=100,
                desc=label,
                leave=True,
                file=sys.stderr,
                bar_format="{desc:<28}{percentage:3.0f}%|{bar:30}| {elapsed}",
            )
        except ImportError:  # pragma: no cover - tqdm is installed by the set-up
            self.bar = None
        self.last = 0

    def __call__(self, fraction):
        value = int(round(100 * min(max(fraction, 0.0), 1.0)))
        if value > self.last:
            if self.bar is not None:
                self.bar.update(value - self.last)
            self.last = value

    def close(self):
        self(1.0)
        if self.bar is not None:
            self.bar.close()


def _step(label, func, *args, **kwargs):
    bar = _Progress(label)
    t0 = time.perf_counter()
    try:
        out = func(*args, progress=bar, **kwargs)
    finally:
        bar.close()
    return out, time.perf_counter() - t0


# Surface formats the CLI hands to VTK (through pyvista.read).
_SURFACE_TYPES = (".obj", ".stl", ".ply", ".off", ".vtp", ".vtk", ".vtu", ".g", ".glb", ".gltf")


def _check_surface_file(path):
    """Refuse what can be refused without VTK: a missing, empty or unknown file, and the
    PLY, STL and legacy-VTK headers and sizes. VTK's readers crash on some corrupt or
    truncated files; this says which file and why instead."""
    if not path.exists():
        raise UsageError(f"no such file: {path}")
    if not path.is_file():
        raise UsageError(f"{path} is not a file")
    if not os.access(path, os.R_OK):
        raise UsageError(f"{path} is not readable (permissions)")
    ext = path.suffix.lower()
    if ext not in _SURFACE_TYPES:
        raise UsageError(
            f"{path}: unsupported file type '{path.suffix}' (hoembed run reads "
            + " ".join(_SURFACE_TYPES)
            + ")"
        )
    size = path.stat().st_size
    if size == 0:
        raise UsageError(f"{path} is empty")
    if ext == ".ply":
        _check_ply(path, size)
    elif ext == ".stl":
        _check_stl(path, size)
    elif ext == ".vtk":
        with open(path, "rb") as fh:
            head = fh.read(256).split(b"\n")
        if (
            not head[0].startswith(b"# vtk DataFile Version")
            or len(head) < 4
            or head[2].strip().upper() not in (b"ASCII", b"BINARY")
        ):
            raise UsageError(
                f"{path} is not a legacy VTK file (its header lacks "
                "'# vtk DataFile Version' and ASCII/BINARY)"
            )


def _check_ply(path, size):
    from hoembed import _readers

    try:
        fmt, header, body = _readers.ply_elements(path)
    except _readers.PlyError as err:
        raise UsageError(f"{path}: {err}") from None

    # per property ("scalar", size) or ("list", count size, item size), sizes in bytes
    def nbytes(dtype):
        return np.dtype(dtype).itemsize

    elements = [
        (
            name,
            n,
            [
                ("list", nbytes(p[1]), nbytes(p[2])) if len(p) == 3 else ("scalar", nbytes(p[1]))
                for p in props
            ],
        )
        for name, n, props in header
    ]
    counts = {name: n for name, n, _ in elements}
    if counts.get("vertex", 0) == 0 or counts.get("face", 0) + counts.get("tristrips", 0) == 0:
        raise UsageError(f"{path}: the PLY header declares no vertices or no faces")
    if fmt == "ascii":
        _check_ply_ascii(path, body, elements)
        return
    # Binary: the fixed-size blocks must be there in full; a list block needs at least its
    # first record's length for every record (faces of one size: the usual case).
    need, offset = body, body
    order = "<" if fmt == "binary_little_endian" else ">"
    with open(path, "rb") as fh:
        for name, n, props in elements:
            lists = [p for p in props if p[0] == "list"]
            fixed = sum(p[1] for p in props if p[0] == "scalar")
            if not lists:
                need += n * fixed
                offset = need
                continue
            if len(lists) == 1 and n > 0 and props[-1][0] == "list":
                fh.seek(offset + fixed)
                raw = fh.read(lists[0][1])
                if len(raw) < lists[0][1]:
                    break
                code = {1: "B", 2: "H", 4: "I"}[lists[0][1]]
                k = struct.unpack(order + code, raw)[0]
                need += n * (fixed + lists[0][1] + k * lists[0][2])
            break  # later blocks cannot be located without reading every record
    if size < need:
        raise UsageError(
            f"{path}: the binary PLY file is truncated ({size} bytes; its "
            f"header needs at least {need})"
        )


def _check_ply_ascii(path, body, elements):
    with open(path, "rb") as fh:
        fh.seek(body)
        lines = (ln for ln in fh if ln.strip())
        nverts = dict((name, n) for name, n, _ in elements).get("vertex", 0)
        for name, n, props in elements:
            for i in range(n):
                line = next(lines, None)
                if line is None:
                    raise UsageError(
                        f"{path}: the ASCII PLY file ends in element '{name}' "
                        f"{i} of {n} (truncated)"
                    )
                w = line.split()
                try:
                    vals = [float(x) for x in w]
                except ValueError:
                    raise UsageError(
                        f"{path}: element '{name}' {i} is not numbers: {line[:60]!r}"
                    ) from None
                if name == "face":
                    if (
                        not vals
                        or vals[0] != int(vals[0])
                        or vals[0] < 3
                        or len(vals) < 1 + int(vals[0])
                    ):
                        raise UsageError(f"{path}: face {i} is malformed: {line[:60]!r}")
                    ids = vals[1 : 1 + int(vals[0])]
                    if any(v != int(v) or v < 0 or v >= nverts for v in ids):
                        raise UsageError(
                            f"{path}: face {i} names a vertex outside 0.."
                            f"{nverts - 1}: {line[:60]!r}"
                        )
                elif name == "vertex" and len(vals) < len(props):
                    raise UsageError(
                        f"{path}: vertex {i} has {len(vals)} values, the header "
                        f"declares {len(props)}"
                    )


def _check_stl(path, size):
    with open(path, "rb") as fh:
        head = fh.read(84)
    if head.lstrip().startswith(b"solid") and (
        len(head) < 84 or 84 + 50 * struct.unpack("<I", head[80:84])[0] != size
    ):
        return  # ASCII STL: VTK's reader parses it defensively
    if len(head) < 84:
        raise UsageError(f"{path}: the binary STL file is truncated ({size} bytes)")
    n = struct.unpack("<I", head[80:84])[0]
    if size < 84 + 50 * n:
        raise UsageError(
            f"{path}: the binary STL file is truncated ({size} bytes for {n} "
            f"triangles: {84 + 50 * n} expected)"
        )


def _read_child(path, out):
    """Child-process half of _read_surface: read with VTK, keep the surface, write it as
    .vtp. Exit 3 with a message on stderr when the file holds no surface. PLY triangle
    strips (which VTK's reader drops), OFF files (no VTK reader) and glTF scenes
    (multiblocks) go through hoembed._readers."""
    import pyvista

    from hoembed import _readers

    try:
        low = path.lower()
        own = None  # VTK's reader
        if low.endswith(".off"):
            own = _readers.read_off
        elif low.endswith(".ply") and _readers.has_strips(path):
            own = _readers.read_ply
        if own:
            points, tris = own(path)
            data = pyvista.PolyData(
                points, np.hstack([np.full((len(tris), 1), 3), tris]).ravel() if len(tris) else None
            )
        else:
            data = pyvista.read(path)
    except Exception as err:  # pyvista raises several types for unreadable files
        print(f"{err}", file=sys.stderr)
        return 3
    data = _readers.surface_of(data)
    if data is None:
        print("it holds no surface", file=sys.stderr)
        return 3
    if data.n_cells == 0:
        print("it holds no triangles", file=sys.stderr)
        return 3
    # A truncated or corrupt file can give cells whose point ids are garbage.
    from vtkmodules.util.numpy_support import vtk_to_numpy

    for kind, cells in (
        ("polygon", data.GetPolys()),
        ("strip", data.GetStrips()),
        ("line", data.GetLines()),
        ("vertex", data.GetVerts()),
    ):
        ids = vtk_to_numpy(cells.GetConnectivityArray()) if cells is not None else []
        if len(ids) and (ids.min() < 0 or ids.max() >= data.n_points):
            bad = ids[(ids < 0) | (ids >= data.n_points)][0]
            print(
                f"the file is corrupt or truncated: a {kind} names point id {bad}, but "
                f"there are {data.n_points} points",
                file=sys.stderr,
            )
            return 3
    data.save(out, binary=True)
    return 0


def _read_surface(path):
    """Read a surface file in a child process: a reader that crashes (VTK's PLY and legacy
    readers on some corrupt files) kills the child, not the run; the parent reads the
    child's .vtp, written by VTK's own XML writer."""
    import pyvista

    path = pathlib.Path(path)
    _check_surface_file(path)
    tmp = tempfile.mkdtemp(prefix="hoembed-read-")
    try:
        out = os.path.join(tmp, "surface.vtp")
        code = (
            "import sys; from hoembed.cli import _read_child; "
            "sys.exit(_read_child(sys.argv[1], sys.argv[2]))"
        )
        try:
            child = subprocess.run(
                [sys.executable, "-c", code, str(path), out],
                capture_output=True,
                text=True,
                timeout=600,
            )
        except subprocess.TimeoutExpired:
            raise UsageError(f"cannot read {path}: the reader did not finish in 600 s") from None
        if child.returncode < 0:
            name = signal.Signals(-child.returncode).name
            raise UsageError(
                f"cannot read {path}: VTK's reader crashed on it ({name}); the "
                "file is probably corrupt or truncated"
            )
        if child.returncode != 0 or not os.path.isfile(out):
            lines = [ln.strip() for ln in child.stderr.splitlines() if ln.strip()]
            why = next(
                (ln for ln in reversed(lines) if not ln.startswith(("Traceback", "File "))),
                f"exit code {child.returncode}",
            )
            raise UsageError(f"cannot read {path}: {why}")
        # VTK's readers report a short read (a truncated binary legacy file) only as a
        # message and return uninitialised point ids: such a message refuses the file.
        said = [
            ln.split("| ", 1)[-1].replace("\x1b[0m", "").strip()
            for ln in child.stderr.splitlines()
            if "ERR|" in ln or ("WARN|" in ln and "rror" in ln)
        ]
        if said:
            raise UsageError(
                f"cannot read {path}: VTK's reader reported '{said[0]}': the "
                "file is probably corrupt or truncated"
            )
        data = pyvista.read(out)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if data.n_cells == 0:
        raise UsageError(f"{path} holds no triangles")
    return data


def _clamp_mask(mesh, args, default_sphere=None):
    pts = mesh.points
    if args.clamp_sphere is not None or (args.clamp_axis is None and default_sphere is not None):
        x, y, z, r = args.clamp_sphere if args.clamp_sphere is not None else default_sphere
        mask = np.linalg.norm(pts - np.array([x, y, z]), axis=1) <= r
    else:
        axis = "xyz".index(args.clamp_axis or "x")
        lo, hi = pts[:, axis].min(), pts[:, axis].max()
        cut = args.clamp_fraction * (hi - lo)
        mask = pts[:, axis] <= lo + cut if args.clamp_side == "min" else pts[:, axis] >= hi - cut
    if not mask.any():
        raise UsageError(
            "the clamped region holds no FE node: widen it (--clamp-fraction, --clamp-sphere)"
        )
    return mask


def _simulate_and_transfer(hoembed, mesh, embedded, args, mask, label):
    frames, t_sim = _step(
        f"simulate ({label})",
        _simulate_progress(hoembed),
        mesh,
        steps=args.steps,
        dt=args.dt,
        young=args.young,
        poisson=args.poisson,
        density=args.density,
        gravity=tuple(args.gravity),
        fixed=mask.astype(np.uint8),
        **({} if args.material is None else {"material": args.material}),
    )
    t0 = time.perf_counter()
    surfaces = []
    for f in frames:
        s = hoembed.transfer(embedded, f, normals=args.normals)
        s.field_data[N.TimeValue] = f.field_data[N.TimeValue]
        surfaces.append(s)
    return frames, surfaces, t_sim, time.perf_counter() - t0


def _simulate_progress(hoembed):
    def run(mesh, progress, **kw):
        return hoembed.simulate(mesh, progress=lambda i, n: progress((i + 1) / n), **kw)

    return run


def _picture(path, tet10_surface, tet4_surface, rest_surface, tet10_mesh, tet4_mesh):
    import pyvista

    pyvista.OFF_SCREEN = True
    pl = pyvista.Plotter(shape=(1, 2), off_screen=True, window_size=(1600, 800), border=False)
    for col, (surf, mesh, title) in enumerate(
        (
            (tet4_surface, tet4_mesh, "tet4 + barycentric"),
            (tet10_surface, tet10_mesh, "tet10 + normal-offset (HOEmbed)"),
        )
    ):
        pl.subplot(0, col)
        pl.add_text(title, font_size=14)
        pl.add_mesh(rest_surface, color="white", opacity=0.15)
        pl.add_mesh(surf, color="tan", smooth_shading=True, specular=0.3)
        pl.add_mesh(mesh.extract_all_edges(), color="steelblue", opacity=0.25, line_width=1)
        pl.view_xz()
        pl.camera.elevation = 25
        pl.camera.azimuth = -20
    pl.link_views()
    pl.screenshot(str(path))
    pl.close()


def _no_display_reason():
    """Why no picture can be rendered here, or None. Debian's VTK renders through X11
    only: without an X display it aborts the process."""
    if sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
        return "no display (DISPLAY is not set)"
    return None


def _picture_isolated(path, *args, timeout=300):
    """Render the picture in a forked child, so that a renderer that aborts (an X display
    that cannot be opened) or hangs costs the picture, not the run. Returns None on
    success, else why it failed."""
    if not hasattr(os, "fork"):
        _picture(path, *args)
        return None
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:  # child: render, never return into the caller's code
        code = 1
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 2)  # VTK's X11 errors would interleave with the parent's
            _picture(path, *args)
            code = 0
        finally:
            os._exit(code)
    deadline = time.monotonic() + timeout
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        if time.monotonic() > deadline:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            return f"the renderer did not finish in {timeout} s"
        time.sleep(0.05)
    if os.WIFSIGNALED(status):
        return f"the renderer died ({signal.Signals(os.WTERMSIG(status)).name})"
    if os.WEXITSTATUS(status) != 0 or not os.path.isfile(path):
        return "the renderer failed"
    return None


# the options that set a driver's property: their ranges and sentences are the driver's
_DRIVER_OPTIONS = (
    ("elements", "mesher", "TargetNumberOfElements"),
    ("dt", "stepper", "TimeStep"),
    ("young", "stepper", "YoungModulus"),
    ("poisson", "stepper", "PoissonRatio"),
    ("density", "stepper", "Density"),
)


def _check_options(args):
    """Every option, before anything is read, meshed or written."""
    if args.steps <= 0:  # the CLI's own rule (the stepper accepts 0 steps)
        raise UsageError("--steps must be positive")
    checks = [
        ("--" + flag, driver, prop, getattr(args, flag)) for flag, driver, prop in _DRIVER_OPTIONS
    ]
    checks += [("--gravity", "stepper", "Gravity", g) for g in args.gravity]
    for flag, driver, prop, value in checks:
        error = check_range(driver, prop, value)
        if error:
            raise UsageError(f"{flag}: {error}")
    if not (math.isfinite(args.clamp_fraction) and 0.0 < args.clamp_fraction <= 1.0):
        raise UsageError(
            f"--clamp-fraction must be a finite number > 0 and <= 1, got {args.clamp_fraction!r}"
        )
    if args.clamp_sphere is not None:
        if not all(math.isfinite(v) for v in args.clamp_sphere) or args.clamp_sphere[3] <= 0:
            raise UsageError(
                f"--clamp-sphere must be finite with a positive radius, got {args.clamp_sphere}"
            )
    _check_output(pathlib.Path(args.output))


def _check_output(out):
    """The output folder must be creatable and writable; nothing is created here."""
    if out.exists():
        if not out.is_dir():
            raise UsageError(f"--output {out} exists and is not a folder")
        if not os.access(out, os.W_OK | os.X_OK):
            raise UsageError(f"--output {out} is not writable")
        for name in ("fe_mesh.pvd", "surface.pvd", "summary.json", "comparison.png"):
            if (out / name).is_dir():
                raise UsageError(f"--output {out}: {out / name} is a folder")
        return
    parent = out.absolute().parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise UsageError(f"--output {out}: {parent} is not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise UsageError(f"--output {out}: cannot create it in {parent} (not writable)")


class _Outputs:
    """What this run wrote, so that a failure removes it (and the output folder when the
    run created it)."""

    def __init__(self, folder):
        self.folder = folder
        self.created = not folder.exists()
        self.paths = []

    def make_folder(self):
        self.folder.mkdir(parents=True, exist_ok=True)

    def add(self, path):
        self.paths.append(pathlib.Path(path))

    def remove_all(self):
        for p in self.paths:
            if p.suffix == ".pvd":
                shutil.rmtree(p.with_suffix(""), ignore_errors=True)
            try:
                p.unlink()
            except OSError:
                pass
        if self.created:
            shutil.rmtree(self.folder, ignore_errors=True)


def main(argv=None):
    args = _parser().parse_args(argv)
    if args.command == "live":
        from .live import run_cli

        return run_cli(args)
    import hoembed

    outputs = None
    try:
        _check_options(args)
        out = pathlib.Path(args.output)
        default_sphere = None
        if args.command == "demo":
            surface = hoembed.thorny_tail()
            source = "built-in thorny tail (hoembed.thorny_tail)"
            default_sphere = (0.0, 0.0, 0.0, 0.6)  # the tail's head
        else:
            surface = _read_surface(args.surface)
            source = str(args.surface)
            if args.clamp_axis is None and args.clamp_sphere is None:
                args.clamp_axis = "x"
        summary = dict(
            input=source, surface_points=surface.n_points, surface_triangles=surface.n_cells
        )
        print(f"surface: {source}: {surface.n_points} points, {surface.n_cells} cells")

        # Meshes, embeddings and clamp masks of both runs first: a clamp region that holds
        # no tet4 node fails here, before anything is simulated or written.
        mesh, t_mesh = _step("tet10 mesh", hoembed.tet10_mesh, surface, n_elements=args.elements)
        embedded, t_embed = _step("embedding (normal-offset)", hoembed.embed, surface, mesh)
        mask = _clamp_mask(mesh, args, default_sphere)
        if not args.no_tet4:
            # The paper's baseline: linear tets with about as many nodes, barycentric mapping.
            mesh4, _ = _step(
                "tet4 mesh (baseline)",
                hoembed.tet10_mesh,
                surface,
                n_elements=max(4 * args.elements, 50),
                order=1,
            )
            emb4, _ = _step(
                "embedding (barycentric)", hoembed.embed, surface, mesh4, method="barycentric"
            )
            mask4 = _clamp_mask(mesh4, args, default_sphere)
        frames, surfaces, t_sim, t_transfer = _simulate_and_transfer(
            hoembed, mesh, embedded, args, mask, "tet10"
        )
        if not args.no_tet4:
            frames4, surfaces4, _, _ = _simulate_and_transfer(
                hoembed, mesh4, emb4, args, mask4, "tet4"
            )

        # Everything computed: now write (each series atomically; a failure removes what
        # this run wrote).
        outputs = _Outputs(out)
        outputs.make_folder()
        fe_pvd = hoembed.write_series(frames, out, "fe_mesh")
        outputs.add(fe_pvd)
        surf_pvd = hoembed.write_series(surfaces, out, "surface")
        outputs.add(surf_pvd)
        summary.update(
            fe_elements=mesh.n_cells,
            fe_nodes=mesh.n_points,
            relaxed_boundary_nodes=int(mesh.field_data["RelaxedNodeCount"][0]),
            max_embedding_residual=float(np.max(embedded.point_data["EmbeddingResidual"])),
            frames=len(frames),
            seconds=dict(
                mesh=round(t_mesh, 2),
                embed=round(t_embed, 2),
                simulate=round(t_sim, 2),
                transfer_all_frames=round(t_transfer, 2),
            ),
            files=dict(fe_mesh=fe_pvd, surface=surf_pvd),
        )
        if not args.no_tet4:
            summary.update(tet4_elements=mesh4.n_cells, tet4_nodes=mesh4.n_points)
            tip10 = np.linalg.norm(frames[-1].point_data["Displacement"], axis=1).max()
            tip4 = np.linalg.norm(frames4[-1].point_data["Displacement"], axis=1).max()
            summary.update(max_displacement_tet10=float(tip10), max_displacement_tet4=float(tip4))
            if not args.no_picture:
                pic = out / "comparison.png"
                why = _no_display_reason()
                if why is None:
                    outputs.add(pic)
                    why = _picture_isolated(
                        pic, surfaces[-1], surfaces4[-1], surface, frames[-1], frames4[-1]
                    )
                if why is None:
                    summary["files"]["picture"] = str(pic)
                else:
                    print(
                        f"hoembed: notice: comparison picture skipped: {why} (run under "
                        "xvfb-run for a picture, or pass --no-picture)",
                        file=sys.stderr,
                    )
                    summary["picture_skipped"] = why
        part = out / "summary.json.part"
        outputs.add(part)
        part.write_text(json.dumps(summary, indent=1))
        os.replace(part, out / "summary.json")
    except (UsageError, hoembed.HOEmbedError, OSError) as err:
        if outputs is not None:
            outputs.remove_all()
        if isinstance(err, OSError) and err.filename:
            err = f"cannot write {err.filename}: {err.strerror}"
        print(f"hoembed: error: {err}", file=sys.stderr)
        return 2
    except BaseException:
        if outputs is not None:
            outputs.remove_all()
        raise

    print("\nsummary")
    print(f"  FE mesh   : {summary['fe_elements']} tet10 elements, {summary['fe_nodes']} nodes")
    if "tet4_elements" in summary:
        print(
            f"  baseline  : {summary['tet4_elements']} tet4 elements, {summary['tet4_nodes']} nodes"
        )
        print(
            f"  max displacement: tet10 {summary['max_displacement_tet10']:.4g}, "
            f"tet4 {summary['max_displacement_tet4']:.4g} (tet4 locks at nu = {args.poisson})"
        )
    print("  seconds   : " + ", ".join(f"{k} {v}" for k, v in summary["seconds"].items()))
    for k, v in summary["files"].items():
        print(f"  {k:<10}: {v}")
    print(f"  summary   : {out / 'summary.json'}")
    print(
        "Open the .pvd files in ParaView, or in Python: "
        f"pyvista.read('{summary['files']['surface']}')"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
