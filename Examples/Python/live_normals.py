"""The live window's shading normals two ways, side by side on the same frame: recomputed
from the deformed triangles (left, LiveSession(point_normals="recompute"), the transfer
filter's RECOMPUTE_POINT_NORMALS) and the rest normals carried by the deformation
gradient in the transfer's own pass (right, "transform", the session's default;
TRANSFORM_POINT_NORMALS). The built-in tail as `hoembed live` shows it (1000
tet10), its tip dragged on bench_live.py's circle; the positions are the same bits in both.
Prints the angle between the two normals (median, 99th percentile, max) and the
difference of the two pictures (per pixel and channel, 0-255), drawn times 4 as a third
panel.

    xvfb-run -a -s "-screen 0 1280x1024x24" .venv/bin/python Examples/Python/live_normals.py \
        [out.png] [--vertices N] [--amplitude 1]

(a 24-bit screen: xvfb-run's default 8-bit one dithers, and the two pictures then differ
everywhere by the dithering)
"""

import argparse

import hoembed
import numpy as np
import pyvista as pv
from hoembed.live import LiveSession, default_clamp

ap = argparse.ArgumentParser()
ap.add_argument("out", nargs="?", default="live_normals.png")
ap.add_argument(
    "--vertices",
    type=int,
    default=0,
    help="fine surface vertices (default: the built-in tail as `hoembed live`)",
)
ap.add_argument(
    "--amplitude",
    type=float,
    default=1.0,
    help="radius of the tip's circle (bench_live.py's drag: 1, a tenth of the tail)",
)
args = ap.parse_args()

coarse = hoembed.thorny_tail()
fe = hoembed.tet10_mesh(coarse, n_elements=1000)
fine = (
    coarse
    if args.vertices <= 0
    else hoembed.thorny_tail(rings=max(8, round(args.vertices / 512)), sectors=512)
)
session = LiveSession(fe, hoembed.embed(fine, fe), fixed=default_clamp(fe, builtin=True))
pos = session.positions()
tip = pos[np.argmax(pos[:, 0])]
session.grab(tip)
for k in range(1, 61):  # half a turn of bench_live.py's circle, scaled
    a = 2 * np.pi * k / 120.0
    session.drag(tip + args.amplitude * np.array([0.0, np.sin(a), 1.0 - np.cos(a)]))
    session.step()


def frame(mode):
    session.point_normals = mode
    session.refresh()  # the same frame's transfer, no step
    out = pv.PolyData()
    out.deep_copy(session.surface)
    return out


recomputed, transformed = frame("recompute"), frame("transform")
assert np.array_equal(recomputed.points, transformed.points)
a = np.asarray(recomputed.point_data["Normals"], float)
b = np.asarray(transformed.point_data["Normals"], float)
ang = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", a, b), -1.0, 1.0)))
stats = (
    f"angle transformed vs recomputed: median {np.median(ang):.3f}, 99th percentile "
    f"{np.percentile(ang, 99):.2f}, max {ang.max():.1f} degrees "
    f"({recomputed.n_points} vertices)"
)


def render(mesh, label):
    pl = pv.Plotter(window_size=(450, 480), off_screen=True)
    actor = pl.add_mesh(mesh, color="#d8b48a")
    actor.prop.interpolation = "gouraud"  # the mesh's own point normals, as the window
    pl.add_text(label, position="upper_left", font_size=9)
    pl.view_xy()
    pl.camera.zoom(1.3)
    img = pl.screenshot(return_img=True)
    pl.close()
    return img


left = render(recomputed, "recomputed (area-weighted)")
right = render(transformed, "transformed: cof(F) n0")
# the difference of the shaded pictures below the labels (top 30 rows)
diff = np.abs(left.astype(int) - right.astype(int))
diff[:30] = 0
import vtkmodules.vtkIOImage as vio  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402

# left | right | the difference of the unlabelled pictures, times 4 (white: 64 or more)
panel = np.repeat(np.clip(4 * diff.max(axis=2), 0, 255).astype(np.uint8)[..., None], 3, axis=2)
both = np.concatenate([left, right, panel], axis=1)[::-1]  # image rows bottom-up
img = vtkImageData()
img.SetDimensions(both.shape[1], both.shape[0], 1)
img.GetPointData().SetScalars(numpy_to_vtk(both.reshape(-1, both.shape[2]), deep=True))
w = vio.vtkPNGWriter()
w.SetFileName(args.out)
w.SetInputData(img)
w.Write()
print(
    f"wrote {args.out}: {stats}; picture difference: max {diff.max()}, "
    f"mean {diff.mean():.3f}, pixels differing by more than 8: "
    f"{np.count_nonzero(diff.max(axis=2) > 8)} of {diff.shape[0] * diff.shape[1]}"
)
