"""The live app (hoembed.live) driven headless under Xvfb: synthetic mouse events through
VTK's interactor (pick, drag, release), keys, the loop's frames, a screenshot."""

import os

import hoembed
import numpy as np
import pytest
import pyvista as pv
from hoembed.live import LiveApp, LiveSession, prepare

pytestmark = pytest.mark.skipif(
    not os.environ.get("DISPLAY"), reason="needs an X display (make test runs under Xvfb)"
)


@pytest.fixture(scope="module")
def small_model():
    surface = hoembed.thorny_tail(rings=120, sectors=48)
    return prepare(surface, n_elements=300, progress=False)


def make_app(small_model, baseline=None):
    surface, fe, emb, clamp = small_model
    session = LiveSession(fe, emb, fixed=clamp)
    pl = pv.Plotter(window_size=(640, 480))
    app = LiveApp(session, plotter=pl, baseline=baseline)
    pl.show(interactive_update=True, auto_close=False)
    iren = app.connect()
    return app, iren


def mouse(iren, event, x, y):
    iren.SetEventInformation(int(x), int(y), 0, 0, "\0", 0, None)
    iren.InvokeEvent(event)


def key(iren, sym):
    iren.SetKeySym(sym)
    iren.SetKeyCode(" " if sym == "space" else sym)
    iren.InvokeEvent("KeyPressEvent")
    iren.InvokeEvent("CharEvent")
    iren.InvokeEvent("KeyReleaseEvent")


def test_drag_moves_surface_and_screenshot(small_model, tmp_path):
    app, iren = make_app(small_model)
    s = app.session
    rest = np.array(s.surface.points)
    # a point near the tail's tip that faces the camera (not on the silhouette)
    camera = np.array(app.pl.camera.position)
    normals = np.asarray(s.surface.point_data["Normals"])
    near_tip = np.flatnonzero(rest[:, 0] > rest[:, 0].max() - 0.3)
    facing = np.einsum("ij,ij->i", normals[near_tip], camera - rest[near_tip])
    tip = rest[near_tip[np.argmax(facing)]]
    x, y = np.round(app.display_of(tip))
    mouse(iren, "LeftButtonPressEvent", x, y)
    assert app.dragging and s.grabbed is not None and len(s.grabbed) > 0
    picked = app.session.grab_point
    assert np.linalg.norm(picked - tip) < 3 * s.h  # the pick hit the surface near the tip
    for k in range(1, 31):  # drag 120 pixels up over 30 frames
        mouse(iren, "MouseMoveEvent", x, y + 4 * k)
        iren.InvokeEvent("TimerEvent")  # what the repeating timer sends: one frame
    # the camera did not turn while dragging
    np.testing.assert_allclose(app.pl.camera.position, camera)
    target = s.target_point
    assert np.linalg.norm(target - picked) > 2 * s.h
    moved = np.linalg.norm(np.asarray(s.surface.points) - rest, axis=1)
    near = np.linalg.norm(rest - picked, axis=1) < s.h
    # the surface near the grab follows the drag (most of the way after 30 frames)
    assert moved[near].max() > 0.5 * np.linalg.norm(target - picked)
    # the clamped head did not move
    assert s.fixed.any()
    assert np.abs(s.fe.point_data["Displacement"][s.fixed]).max() == 0.0
    mouse(iren, "LeftButtonReleaseEvent", x, y + 120)
    assert not app.dragging and s.grabbed is None
    for _ in range(5):
        app.tick()
    assert s.time == pytest.approx(35 * s.dt)
    path = tmp_path / "live.png"
    img = app.pl.screenshot(str(path))
    assert path.stat().st_size > 0
    # not blank: the surface covers a good part of the picture, in several shades
    background = img[0, 0]
    covered = np.any(np.abs(img.astype(int) - background) > 30, axis=-1).mean()
    assert covered > 0.02, covered
    assert len(np.unique(img.reshape(-1, img.shape[-1]), axis=0)) > 50
    assert "frame" in app.status and "t = 0.58" in app.status
    app.pl.close()


def test_press_off_surface_turns_camera_and_keys(small_model):
    app, iren = make_app(
        small_model,
        baseline=lambda: LiveSession(
            *prepare(small_model[0], n_elements=300, progress=False, order=1)[1:3]
        ),
    )
    s = app.session
    camera = np.array(app.pl.camera.position)
    mouse(iren, "LeftButtonPressEvent", 2, 2)  # a corner: background
    assert not app.dragging
    mouse(iren, "MouseMoveEvent", 60, 40)
    mouse(iren, "LeftButtonReleaseEvent", 60, 40)
    assert not np.allclose(app.pl.camera.position, camera)  # the trackball turned it
    app.tick()
    t = s.time
    key(iren, "space")
    assert app.paused
    app.tick()
    assert s.time == t
    key(iren, "space")
    key(iren, "m")
    assert app.show_mesh and app.mesh_actor.GetVisibility()
    key(iren, "b")  # tet4 + barycentric beside it, stepped with it
    assert app.show_baseline and app.baseline is not None
    app.tick()
    assert app.baseline.time == pytest.approx(s.dt)
    key(iren, "r")
    assert s.time == 0.0 and app.baseline.time == 0.0
    app.pl.close()


def test_live_function_and_cli(small_model, tmp_path, capsys):
    from hoembed.cli import main

    pl = pv.Plotter(window_size=(320, 240))
    app = hoembed.live(small_model[0], n_elements=300, plotter=pl, run=False)
    assert isinstance(app, LiveApp) and app.session.kind == "tet10"
    app.tick()
    assert app.session.time > 0
    pl.close()
    # bad input: a clear error, exit code 2, no window
    assert main(["live", str(tmp_path / "missing.obj")]) == 2
    assert "hoembed live: error: no such file" in capsys.readouterr().err
    assert main(["live", "--elements", "2"]) == 2
    with pytest.raises(SystemExit):
        main(["live", "--help"])
    assert "--elements" in capsys.readouterr().out
