"""A scripted drag in the live window: what `hoembed live` does when the user pulls the
thorny tail's tip, without a user (runs under Xvfb). Saves a picture of the window
mid-drag: tet10 + normal-offset (left) and tet4 + barycentric (right), FE mesh shown.

    xvfb-run -a .venv/bin/python Examples/Python/live_drag.py [out.png]
"""

import sys

import hoembed
import numpy as np
import pyvista as pv

out = sys.argv[1] if len(sys.argv) > 1 else "live_drag.png"
pl = pv.Plotter(window_size=(900, 480), off_screen=False)
app = hoembed.live(plotter=pl, run=False)  # the built-in tail, 1000 tet10
pl.show(interactive_update=True, auto_close=False)
app.key("b")  # tet4 + barycentric beside it
app.key("m")  # FE mesh wireframe
s = app.session
rest = np.asarray(s.surface.points).copy()
tip = rest[np.argmax(rest[:, 0])]
camera = np.asarray(pl.camera.position)
# press on a surface point near the tip that faces the camera, then drag it up
normals = np.asarray(s.surface.point_data["Normals"])
near = np.flatnonzero(rest[:, 0] > rest[:, 0].max() - 0.4)
grab = near[np.argmax(np.einsum("ij,ij->i", normals[near], camera - rest[near]))]
x, y = np.round(app.display_of(rest[grab]))
assert app.press(x, y), "the press missed the surface"
for k in range(1, 46):
    app.move(x, y + 3 * k)
    app.tick()
pl.screenshot(out)
print(f"wrote {out}: t = {s.time:.2f} s, last frame {app.frame_ms:.0f} ms")
