"""The ``hoembed`` command: the whole pipeline on a surface file or the built-in model.

    hoembed demo [--output output]          # built-in thorny tail, defaults below
    hoembed run SURFACE [options]           # any surface file VTK/pyvista reads

Pipeline: fine surface -> tet10 mesh (vtkTet10Mesher) -> embedding coordinates
(vtkEmbeddingCoordinatesFilter) -> co-rotated FE simulation under gravity with a clamped
region (vtkCorotationalFEMStepper) -> deformed fine surface per frame
(vtkDeformationTransferFilter) -> .pvd time series of the FE mesh and of the surface,
plus a picture comparing tet4 + barycentric with tet10 + normal-offset on the last frame.
"""
import argparse
import json
import os
import pathlib
import sys
import time

import numpy as np

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
        prog="hoembed", description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter, epilog=EPILOG)
    sub = p.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="run the pipeline on the built-in thorny tail",
                          formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    run = sub.add_parser("run", help="run the pipeline on a surface file",
                         formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    run.add_argument("surface", help="closed triangle surface (.obj .stl .ply .vtp .vtk ...)")
    for sp, defaults in ((demo, dict(steps=40, dt=0.02, young=1e7, gravity=(0.0, 0.0, -9.81),
                                     elements=1000)),
                         (run, dict(steps=40, dt=0.02, young=1e5, gravity=(0.0, 0.0, -9.81),
                                    elements=1000))):
        sp.add_argument("--output", default="output", help="output folder")
        sp.add_argument("--elements", type=int, default=defaults["elements"],
                        help="target number of tet10 elements")
        sp.add_argument("--young", type=float, default=defaults["young"],
                        help="Young's modulus E (Pa)")
        sp.add_argument("--poisson", type=float, default=0.49, help="Poisson's ratio")
        sp.add_argument("--density", type=float, default=1000.0, help="density (kg/m^3)")
        sp.add_argument("--gravity", type=float, nargs=3, default=defaults["gravity"],
                        metavar=("GX", "GY", "GZ"), help="gravity (m/s^2)")
        sp.add_argument("--steps", type=int, default=defaults["steps"], help="time steps")
        sp.add_argument("--dt", type=float, default=defaults["dt"], help="time step (s)")
        sp.add_argument("--clamp-axis", choices="xyz", default=None,
                        help="clamp the nodes at one end along this axis (with --clamp-side)")
        sp.add_argument("--clamp-side", choices=("min", "max"), default="min")
        sp.add_argument("--clamp-fraction", type=float, default=0.1,
                        help="thickness of the clamped end, as a fraction of the extent")
        sp.add_argument("--clamp-sphere", type=float, nargs=4, default=None,
                        metavar=("X", "Y", "Z", "R"), help="clamp the nodes inside a sphere")
        sp.add_argument("--normals", choices=("recompute", "rotate", "deform"),
                        default="recompute",
                        help="deformed normal field of the transfer: recompute (the paper's "
                             "smooth normals of the deformed boundary, default), rotate "
                             "(rest normals rotated by the nodal rotations) or deform (rest "
                             "normals pushed forward by the nodal deformation gradient: "
                             "surface detail leans with a shear of the surface)")
        sp.add_argument("--no-picture", action="store_true", help="skip the comparison picture")
        sp.add_argument("--no-tet4", action="store_true",
                        help="skip the tet4 + barycentric baseline (and the picture)")
    return p


class _Progress:
    """A one-line progress bar on stderr (tqdm when available)."""

    def __init__(self, label):
        self.label = label
        try:
            from tqdm import tqdm
            self.bar = tqdm(total=100, desc=label, leave=True, file=sys.stderr,
                            bar_format="{desc:<28}{percentage:3.0f}%|{bar:30}| {elapsed}")
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


def _read_surface(path):
    import pyvista
    path = pathlib.Path(path)
    if not path.is_file():
        raise UsageError(f"no such file: {path}")
    try:
        data = pyvista.read(str(path))
    except Exception as err:  # pyvista raises several types for unreadable files
        raise UsageError(f"cannot read {path}: {err}") from None
    if not isinstance(data, pyvista.PolyData):
        try:
            data = data.extract_surface()
        except Exception:
            raise UsageError(f"{path} holds no surface") from None
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
        raise UsageError("the clamped region holds no FE node: widen it (--clamp-fraction, "
                         "--clamp-sphere)")
    return mask


def _simulate_and_transfer(hoembed, mesh, embedded, args, mask, label):
    frames, t_sim = _step(f"simulate ({label})", _simulate_progress(hoembed), mesh, steps=args.steps,
                          dt=args.dt, young=args.young, poisson=args.poisson,
                          density=args.density, gravity=tuple(args.gravity),
                          fixed=mask.astype(np.uint8))
    t0 = time.perf_counter()
    surfaces = []
    for f in frames:
        s = hoembed.transfer(embedded, f, normals=args.normals)
        s.field_data["TimeValue"] = f.field_data["TimeValue"]
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
            ((tet4_surface, tet4_mesh, "tet4 + barycentric"),
             (tet10_surface, tet10_mesh, "tet10 + normal-offset (HOEmbed)"))):
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


def main(argv=None):
    args = _parser().parse_args(argv)
    import pyvista
    import hoembed

    try:
        for name in ("elements", "steps"):
            if getattr(args, name) <= 0:
                raise UsageError(f"--{name} must be positive")
        if args.dt <= 0:
            raise UsageError("--dt must be positive")
        out = pathlib.Path(args.output)
        out.mkdir(parents=True, exist_ok=True)
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
        summary = dict(input=source, surface_points=surface.n_points,
                       surface_triangles=surface.n_cells)
        print(f"surface: {source}: {surface.n_points} points, {surface.n_cells} cells")

        mesh, t_mesh = _step("tet10 mesh", hoembed.tet10_mesh, surface, n_elements=args.elements)
        embedded, t_embed = _step("embedding (normal-offset)", hoembed.embed, surface, mesh)
        mask = _clamp_mask(mesh, args, default_sphere)
        frames, surfaces, t_sim, t_transfer = _simulate_and_transfer(
            hoembed, mesh, embedded, args, mask, "tet10")
        fe_pvd = hoembed.write_series(frames, out, "fe_mesh")
        surf_pvd = hoembed.write_series(surfaces, out, "surface")
        summary.update(
            fe_elements=mesh.n_cells, fe_nodes=mesh.n_points,
            relaxed_boundary_nodes=int(mesh.field_data["RelaxedNodeCount"][0]),
            max_embedding_residual=float(np.max(embedded.point_data["EmbeddingResidual"])),
            frames=len(frames), seconds=dict(mesh=round(t_mesh, 2), embed=round(t_embed, 2),
                                             simulate=round(t_sim, 2),
                                             transfer_all_frames=round(t_transfer, 2)),
            files=dict(fe_mesh=fe_pvd, surface=surf_pvd))

        if not args.no_tet4:
            # The paper's baseline: linear tets with about as many nodes, barycentric mapping.
            mesh4, _ = _step("tet4 mesh (baseline)", hoembed.tet10_mesh, surface,
                             n_elements=max(4 * args.elements, 50), order=1)
            emb4, _ = _step("embedding (barycentric)", hoembed.embed, surface, mesh4,
                            method="barycentric")
            mask4 = _clamp_mask(mesh4, args, default_sphere)
            frames4, surfaces4, _, _ = _simulate_and_transfer(
                hoembed, mesh4, emb4, args, mask4, "tet4")
            summary.update(tet4_elements=mesh4.n_cells, tet4_nodes=mesh4.n_points)
            tip10 = np.linalg.norm(frames[-1].point_data["Displacement"], axis=1).max()
            tip4 = np.linalg.norm(frames4[-1].point_data["Displacement"], axis=1).max()
            summary.update(max_displacement_tet10=float(tip10), max_displacement_tet4=float(tip4))
            if not args.no_picture:
                pic = out / "comparison.png"
                _picture(pic, surfaces[-1], surfaces4[-1], surface, frames[-1], frames4[-1])
                summary["files"]["picture"] = str(pic)
        (out / "summary.json").write_text(json.dumps(summary, indent=1))
    except (UsageError, hoembed.HOEmbedError, OSError) as err:
        print(f"hoembed: error: {err}", file=sys.stderr)
        return 2

    print("\nsummary")
    print(f"  FE mesh   : {summary['fe_elements']} tet10 elements, {summary['fe_nodes']} nodes")
    if "tet4_elements" in summary:
        print(f"  baseline  : {summary['tet4_elements']} tet4 elements, {summary['tet4_nodes']} nodes")
        print(f"  max displacement: tet10 {summary['max_displacement_tet10']:.4g}, "
              f"tet4 {summary['max_displacement_tet4']:.4g} (tet4 locks at nu = {args.poisson})")
    print("  seconds   : " + ", ".join(f"{k} {v}" for k, v in summary["seconds"].items()))
    for k, v in summary["files"].items():
        print(f"  {k:<10}: {v}")
    print(f"  summary   : {out / 'summary.json'}")
    print("Open the .pvd files in ParaView, or in Python: "
          f"pyvista.read('{summary['files']['surface']}')")
    return 0


if __name__ == "__main__":
    sys.exit(main())
