"""The live loop's scripted run, the same in the VTK build (its reference, written by
generate_reference.py) and in the wheel (test_pip_live.py): a LiveSession on the thorny
tail's tet10 case, clamped at its head, three free frames, a grab of the tip dragged for
four frames, a release, a frame, a reset. Synchronous factorisation (the background one
takes its factor when its thread is done, so its frames depend on timing). The session's
default point normals (transform) in both routes, kept with the points."""

import os

import numpy as np

CASE = "tail_tet10"


def run(root):
    """FE node positions, surface points and point normals of every frame, and the
    times."""
    import pyvista
    from hoembed.live import LiveSession, default_clamp

    fe = pyvista.read(os.path.join(root, CASE, "mesh.vtu"))
    emb = pyvista.read(os.path.join(root, CASE, "embedded_normal-offset.vtp"))
    s = LiveSession(fe, emb, fixed=default_clamp(fe, builtin=True), background_factorization=False)
    assert s.point_normals == "transform"  # the default, in both routes
    frames = {"positions": [], "surface": [], "normals": [], "time": []}

    def keep():
        frames["positions"].append(np.array(s.positions()))
        frames["surface"].append(np.array(s.surface.points))
        frames["normals"].append(np.array(s.surface.point_data["Normals"]))
        frames["time"].append(s.time)

    keep()
    for _ in range(3):
        s.step()
        keep()
    pos = s.positions()
    tip = pos[np.argmax(pos[:, 0])]
    s.grab(tip)
    for k in range(4):
        s.drag(tip + np.array([0.0, 0.1 * (k + 1), 0.05 * (k + 1)]))
        s.step()
        keep()
    s.release()
    s.step()
    keep()
    s.reset()
    keep()
    return {k: np.asarray(v) for k, v in frames.items()}


def write(root):
    if os.path.exists(os.path.join(root, CASE)):
        np.savez(os.path.join(root, "live.npz"), **run(root))
        print("[reference] live loop: 10 frames")
