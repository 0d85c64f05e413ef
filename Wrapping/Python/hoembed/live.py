"""The live loop: grab a point of the fine surface, drag it, and the surface follows.

Two layers, so that tests and benchmarks drive exactly what the window runs:

- :class:`LiveSession` (no window): the stepper's driver in live mode (its clock, loads
  set between steps, background factorisation: what vtkCorotationalFEMStepper's LiveMode
  runs) and the transfer's driver with its plan made once (normal-offset, recomputed
  normals, shading point normals carried by the deformation), through hoembed._hoembed,
  so the loop is the same in the VTK build and the pip wheel. ``grab(point)`` prescribes the FE
  nodes near a surface point, ``drag(point)`` moves their targets with it, ``release()``
  lets go, ``step()`` advances one frame (one time step + the transfer) and returns the
  seconds of each stage.
- :class:`LiveApp` (a pyvista window over one or two sessions): mouse and key handlers
  as plain methods (``press``, ``move``, ``release``, ``key``, ``tick``) that the VTK
  observers call, so the loop can be stepped without an event loop.

``hoembed.live()`` / ``hoembed live [FILE]`` open the window (the built-in thorny tail
without a file). Controls: left-drag on the surface pulls it (left-drag elsewhere turns
the camera), ``space`` pause, ``r`` reset, ``m`` FE mesh wireframe, ``b`` tet4 +
barycentric side by side, ``q`` quit.
"""

import time

import numpy as np
import pyvista
from vtkmodules.vtkRenderingCore import vtkCellPicker

from ._arrays import N
from ._checks import NORMAL_MODES, POINT_NORMALS_MODES, point_normals_argument, simulate_arguments
from ._errors import HOEmbedArgumentError, HOEmbedError
from ._hoembed import DEFAULTS, MATERIALS
from .simulation import build_stepper
from .transfer import TransferPlan

__all__ = ["LiveSession", "LiveApp", "live"]
# the drivers' defaults where the live loop has no setting of its own (its material,
# damping and gravity are its own: a soft, damped solid)
_STEPPER = DEFAULTS["stepper"]
_N_ELEMENTS = DEFAULTS["mesher"]["TargetNumberOfElements"]


def _vtk_view(array):
    """A numpy view (no copy) of a VTK data array's memory."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    view = vtk_to_numpy(array)
    return view.reshape(array.GetNumberOfTuples(), array.GetNumberOfComponents())


def _edge_lengths(points, cells):
    """Mean corner edge length of the cells (rows of node ids, corners first)."""
    p = np.asarray(points)
    e = [
        np.linalg.norm(p[cells[:, a]] - p[cells[:, b]], axis=1)
        for a, b in ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))
    ]
    return float(np.mean(e))


def _element_size(fe_mesh):
    """Mean corner edge length of the mesh (the drag's length scale)."""
    return _edge_lengths(fe_mesh.points, fe_mesh.cell_connectivity.reshape(fe_mesh.n_cells, -1))


def default_clamp(fe_mesh, builtin=False):
    """The clamp of the live demo: the thorny tail's head (the nodes within 0.6 of the
    origin), else the 10% of the nodes' x extent at its low end."""
    pts = np.asarray(fe_mesh.points)
    if builtin:
        mask = np.linalg.norm(pts, axis=1) <= 0.6
    else:
        lo, hi = pts[:, 0].min(), pts[:, 0].max()
        mask = pts[:, 0] <= lo + 0.1 * (hi - lo)
    if not mask.any():
        raise HOEmbedArgumentError("live: the clamped region holds no FE node")
    return mask


class LiveSession:
    """One live simulation: FE mesh + embedded surface, stepped frame by frame.

    Parameters
    ----------
    fe_mesh : pyvista.UnstructuredGrid
        Rest FE mesh (tet10 or tet4).
    embedded : pyvista.PolyData
        The fine surface embedded in ``fe_mesh`` (``hoembed.embed``).
    fixed : array of bool, optional
        Clamped FE nodes (default: none).
    dt : float
        Time step per frame (s), default 1/60.
    young, poisson, density, gravity, rayleigh_mass, rayleigh_stiffness : material and
        loads of vtkCorotationalFEMStepper (defaults: a soft, damped solid without gravity).
    grab_radius : float, optional
        FE nodes within this distance of the picked point are dragged (default: one mean
        element edge; at least the nearest free node).
    speed_limit : float, optional
        PrescribedSpeedLimit of the stepper (default: per grab, half the mean edge of the
        cells around the grabbed nodes per step).
    normals : str
        Transfer normal mode ("recompute", "rotate" or "deform").
    point_normals : {"transform", "recompute"} or bool
        The surface's shading normals, as vtkDeformationTransferFilter's PointNormalsMode:
        ``"transform"`` (default, also True): the rest surface's normals carried by the
        deformation (cof(F) n0, in the transfer's pass; recomputed per vertex where the
        map folds), about 0.6x the cost of ``"recompute"`` (the deformed polygons'
        area-weighted normals; Benchmarks/RESULTS.md). False: none.
    overlap : bool
        Step the next frame on a second thread while the transfer draws this one.
        ``step()`` then shows the state the previous ``step()`` computed: the same
        frames (to the stepper's own run-to-run round-off), one call late (a grab, a
        drag or a release acts on the frame after the next). Default off (each
        ``step()`` shows its own step): on the shared 2-core machine it did not pay
        (Benchmarks/RESULTS.md, live loop).
    solver_tolerance : float, optional
        The stepper's SolverTolerance (default: the stepper's own); a looser one takes
        fewer CG iterations per frame (Benchmarks/RESULTS.md, live loop).
    material : str, optional
        The stepper's Material (default: the stepper's own, ``"corotated"``):
        ``"stvk"``, ``"neo-hookean"`` or ``"mooney-rivlin"`` step by Newton's method.
    newton_iterations : int
        Newton iterations per frame for those laws (MaxNewtonIterations), default 1: a
        frame then costs about twice a co-rotated one at 3000 tet10, a converged one about
        8x (Benchmarks/RESULTS.md, Stepper); a cell is never inverted either way.
    background_factorization : bool
        The stepper's BackgroundFactorization (default on): a grab or a release is
        stepped at once while the new factorisation runs on a thread, instead of a frame
        of about half a second at 3000 tet10 (Benchmarks/RESULTS.md, live loop).
    """

    def __init__(
        self,
        fe_mesh,
        embedded,
        fixed=None,
        dt=1.0 / 60.0,
        young=2e5,
        poisson=0.45,
        density=_STEPPER["Density"],
        gravity=(0.0, 0.0, 0.0),
        rayleigh_mass=1.0,
        rayleigh_stiffness=0.005,
        grab_radius=None,
        speed_limit=None,
        normals="recompute",
        point_normals="transform",
        background_factorization=True,
        overlap=False,
        solver_tolerance=None,
        material=None,
        newton_iterations=1,
    ):
        self.fe_rest = pyvista.wrap(fe_mesh).copy()
        n = self.fe_rest.n_points
        self.fixed = np.zeros(n, bool) if fixed is None else np.asarray(fixed, bool)
        if self.fixed.shape != (n,):
            raise HOEmbedArgumentError(f"live: fixed must have {n} entries (one per FE node)")
        self.fe_rest.point_data[N.Fixed] = self.fixed.astype(np.uint8)
        self.rest = np.asarray(self.fe_rest.points, dtype=float).copy()
        self.h = _element_size(self.fe_rest)
        quadratic = pyvista.CellType.QUADRATIC_TETRA in self.fe_rest.cells_dict
        self.kind = "tet10" if quadratic else "tet4"
        self.dt = float(dt)
        self.grab_radius = self.h if grab_radius is None else float(grab_radius)
        self.auto_speed = speed_limit is None
        self._cells = self.fe_rest.cell_connectivity.reshape(self.fe_rest.n_cells, -1)
        if normals not in NORMAL_MODES:
            raise HOEmbedArgumentError(f"live: normals must be one of {sorted(NORMAL_MODES)}")
        # True: the default mode (the session drew recomputed normals before "transform")
        self._pn_mode = point_normals_argument("live", point_normals, "transform")
        a = simulate_arguments(
            self.fe_rest,
            1,
            self.dt,
            young,
            poisson,
            density,
            gravity,
            rayleigh_mass,
            rayleigh_stiffness,
            1,
            _STEPPER["SolverTolerance"] if solver_tolerance is None else solver_tolerance,
            None,
        )
        if material is not None:  # the law and Newton's controls: checked by the driver
            a.update(
                material=str(material),
                mooney_rivlin=(_STEPPER["MooneyRivlinC10"], _STEPPER["MooneyRivlinC01"]),
                newton_tolerance=_STEPPER["NewtonTolerance"],
                max_newton_iterations=newton_iterations,
            )
        self.material = MATERIALS[_STEPPER["Material"]] if material is None else str(material)
        speed = 0.5 * self.h / self.dt if speed_limit is None else float(speed_limit)
        try:
            st = build_stepper(
                self.fe_rest, a, {}, self.fixed.astype(np.float64), False, False, speed_limit=speed
            )  # (per grab when automatic)
            st.set_background_factorization(bool(background_factorization))
        except HOEmbedError as e:
            raise HOEmbedError(f"live: {e}") from None
        self.stepper = st
        self.mode = NORMAL_MODES[normals]
        self.transfer = TransferPlan(embedded, self.fe_rest, self.mode)
        # the frame's outputs, updated in place (the window's actors draw these objects);
        # the transfer writes straight into the surface's points (no copy per frame)
        self._surface = self.transfer.output(True)
        self.transfer.points = _vtk_view(self._surface.GetPoints().GetData())
        self.overlap = bool(overlap)
        self._worker = None  # the stepping thread of overlap (made on first use)
        # the FE mesh as the stepper's output has it (vtkCorotationalFEMStepper with
        # ComputeDiagnostics off): the state written into its arrays in place
        self._fe = self.fe_rest.copy()
        n = self.fe_rest.n_points
        self._x = np.empty((n, 3))
        pd = self._fe.point_data
        for name, width in ((N.Displacement, 3), (N.Velocity, 3), (N.NodalRotation, 9)):
            pd[name] = np.zeros((n, width))
        self._disp, self._vel, self._rot = (pd[N.Displacement], pd[N.Velocity], pd[N.NodalRotation])
        self.grabbed = None  # FE node ids
        self.grab_start = None  # their positions when grabbed
        self.grab_point = None
        self.target_point = None
        self.frames = 0
        self._frame()  # time 0

    def _frame(self):
        """The current state into the outputs: the FE mesh's points, the transfer."""
        self._write_state()
        self._transfer()

    def _write_state(self):
        """The stepper's current state into the FE mesh output (what the transfer reads)."""
        self.stepper.write_frame(self._x, self._disp, self._vel, self._rot)
        self._fe.points[:] = self._x
        self._fe.GetPoints().Modified()
        for name in (N.Displacement, N.Velocity, N.NodalRotation):
            self._fe.GetPointData().GetArray(name).Modified()
        self._time = self.stepper.clock_step * self.dt

    def _transfer(self):
        """The fine surface (and its point normals) of the FE mesh output's state."""
        # the point normals in the transfer's pass (the driver's TransferFrame.PointNormals),
        # straight into the surface's Normals array
        on = self._pn_mode is not None
        nrm = self._surface.point_data[N.Normals] if on else None
        self.transfer.evaluate(self._x, self._disp, self._rot, nrm, self._pn_mode or 0)
        if on:
            self._surface.GetPointData().GetNormals().Modified()
        self._surface.GetPoints().Modified()

    def refresh(self):
        """The outputs again for the current state, without a step (after a change of
        point_normals: both modes on the same frame)."""
        self._frame()

    @property
    def point_normals(self):
        """The point normals mode ("transform", "recompute") or False (the surface's
        Normals are then left as they were); settable, as the keyword, from the next
        frame (or refresh()) on."""
        return next((k for k, v in POINT_NORMALS_MODES.items() if v == self._pn_mode), False)

    @point_normals.setter
    def point_normals(self, value):
        self._pn_mode = point_normals_argument("live", value, "transform")

    @property
    def folded_normals(self):
        """Transform point normals: surface vertices of the last frame whose normal was
        recomputed because the deformation folds there."""
        return self.transfer.folded_normals if self._pn_mode == 1 else 0

    @property
    def surface(self):
        """The deformed fine surface of the current frame (one object, updated in place
        every frame; the window's actor draws it)."""
        return self._surface

    @property
    def fe(self):
        """The deformed FE mesh of the current frame (one object, updated in place)."""
        return self._fe

    # -- drag -------------------------------------------------------------------------
    def positions(self):
        """Current FE node positions (n, 3)."""
        return np.asarray(self.fe.points)

    def grab(self, point):
        """Prescribe the free FE nodes within grab_radius of `point` (at least the nearest
        one) to move with it. Returns their ids (empty when every node is clamped)."""
        point = np.asarray(point, float)
        pos = self.positions()
        d = np.linalg.norm(pos - point, axis=1)
        d[self.fixed] = np.inf
        near = np.flatnonzero(d <= self.grab_radius)
        if len(near) == 0 and np.isfinite(d.min()):
            near = np.array([int(np.argmin(d))])
        if len(near) == 0:
            return near
        ids = near
        if self.auto_speed:
            # the speed limit from the cells around the grab: near a thin part they are
            # much smaller than the mean, and a move of one of their sizes per step
            # inverts them
            around = self._cells[np.isin(self._cells, ids).any(axis=1)]
            self.stepper.prescribed_speed_limit = 0.5 * _edge_lengths(self.rest, around) / self.dt
        self.grabbed = ids
        self.grab_start = pos[ids].copy()
        self.grab_point = point
        self.drag(point)
        return ids

    def drag(self, point):
        """Move the grabbed nodes' targets by point - (the grabbed point)."""
        if self.grabbed is None:
            return
        self.target_point = np.asarray(point, float)
        n = self.fe_rest.n_points
        mask = np.zeros(n)
        mask[self.grabbed] = 1.0
        target = np.zeros((n, 3))
        target[self.grabbed] = (
            self.grab_start + (self.target_point - self.grab_point) - self.rest[self.grabbed]
        )
        try:
            self.stepper.set_prescribed_motion(mask, target.reshape(-1))
        except RuntimeError as e:
            raise HOEmbedError(f"live: {e}") from None

    def release(self):
        self.grabbed = self.grab_start = self.grab_point = self.target_point = None
        self.stepper.set_prescribed_motion(None, None)

    def reset(self):
        self.release()
        self.stepper.request_reset()
        self.frames = 0
        self._advance()
        self._frame()

    def _advance(self):
        try:
            self.stepper.advance_live()
        except RuntimeError as e:
            raise HOEmbedError(f"live: {e}") from None

    @property
    def time(self):
        """The simulated time of the frame shown (with overlap, the stepper is one step
        ahead)."""
        return self._time

    # -- frame ------------------------------------------------------------------------
    def step(self):
        """One frame: a time step, then the transfer (with point normals). Returns the
        wall seconds of each stage."""
        t0 = time.perf_counter()
        if self.overlap:
            return self._step_overlapped(t0)
        self.stepper.request_steps(1)
        self._advance()
        t1 = time.perf_counter()
        self._frame()
        t2 = time.perf_counter()
        self.frames += 1
        return {"step": t1 - t0, "transfer": t2 - t1}

    def _step_overlapped(self, t0):
        """overlap: the stepper's state (the previous call's step) is shown while the
        next step runs on the worker thread; both calls release the GIL, and the step
        reads nothing the transfer writes (the state is copied out first)."""
        if self._worker is None:
            from concurrent.futures import ThreadPoolExecutor

            self._worker = ThreadPoolExecutor(1, thread_name_prefix="hoembed-live-step")
        self._write_state()
        self.stepper.request_steps(1)

        def advance():
            t = time.perf_counter()
            self._advance()
            return time.perf_counter() - t

        pending = self._worker.submit(advance)
        try:
            t1 = time.perf_counter()
            self._transfer()
            t2 = time.perf_counter()
        finally:
            step = pending.result()  # the stepper is idle between calls
        self.frames += 1
        return {"step": step, "transfer": t2 - t1, "frame": time.perf_counter() - t0}


class LiveApp:
    """A pyvista window over a LiveSession (and, toggled with ``b``, a tet4 +
    barycentric session beside it). The event handlers are plain methods taking display
    coordinates, called by the VTK observers or directly by a test."""

    def __init__(self, session, plotter=None, baseline=None, title="hoembed live"):
        self.session = session
        self.baseline_factory = baseline  # callable -> LiveSession (tet4), made on demand
        self.baseline = None
        self.show_baseline = False
        self.show_mesh = False
        self.paused = False
        self.dragging = False
        self.pl = plotter if plotter is not None else pyvista.Plotter(title=title)
        b = session.surface.bounds
        # the baseline sits beside the model along x; the camera looks along -z
        self.offset = 1.15 * (b[1] - b[0]) + 0.1 * max(b[3] - b[2], b[5] - b[4])
        self.surface_actor = self.pl.add_mesh(
            session.surface, color="#d8b48a", smooth_shading=True, name="surface"
        )
        self.mesh_actor = self.pl.add_mesh(
            session.fe, style="wireframe", color="#2a4d69", opacity=0.5, name="fe"
        )
        # the actors draw the session's outputs (updated in place every frame), not the
        # copies pyvista made when adding them
        self.surface_actor.mapper.SetInputData(session.surface)
        self.mesh_actor.mapper.SetInputData(session.fe)
        self.mesh_actor.SetVisibility(False)
        self.base_actor = None
        self.marker = self.pl.add_mesh(
            pyvista.Sphere(radius=0.3 * session.h), color="red", name="marker"
        )
        self.marker.SetVisibility(False)
        self.text = self.pl.add_text("", position="upper_left", font_size=10, name="status")
        self.pl.add_text(
            "drag the surface | space pause | r reset | m FE mesh | b tet4 side by side | q quit",
            position="lower_left",
            font_size=8,
            name="help",
        )
        self.picker = vtkCellPicker()
        self.picker.SetTolerance(0.0005)
        self.picker.PickFromListOn()
        self.picker.AddPickList(self.surface_actor)
        self.frame_ms = 0.0
        self.stages = {}
        self._drag_depth = None
        self.pl.view_xy()
        self.pl.reset_camera()
        self._update_text()

    # -- geometry helpers -------------------------------------------------------------
    def _renderer(self):
        return self.pl.renderer

    def _world(self, x, y):
        """World point under display (x, y) at the depth of the grabbed point."""
        ren = self._renderer()
        ren.SetDisplayPoint(float(x), float(y), self._drag_depth)
        ren.DisplayToWorld()
        w = ren.GetWorldPoint()
        return np.array(w[:3]) / w[3]

    def display_of(self, point):
        """Display coordinates of a world point (for tests and scripted drags)."""
        ren = self._renderer()
        ren.SetWorldPoint(*point, 1.0)
        ren.WorldToDisplay()
        return ren.GetDisplayPoint()[:2]

    # -- handlers ---------------------------------------------------------------------
    def press(self, x, y):
        """Left button at display (x, y): grab the surface there. False when the press
        missed the surface (the camera then turns)."""
        if not self.picker.Pick(float(x), float(y), 0.0, self._renderer()):
            return False
        p = np.array(self.picker.GetPickPosition())
        if len(self.session.grab(p)) == 0:
            return False
        ren = self._renderer()
        ren.SetWorldPoint(*p, 1.0)
        ren.WorldToDisplay()
        self._drag_depth = ren.GetDisplayPoint()[2]
        if self.baseline is not None:
            self.baseline.grab(p)  # same rest geometry (shown shifted)
            self.baseline.stepper.prescribed_speed_limit = (
                self.session.stepper.prescribed_speed_limit
            )
        self.dragging = True
        self.marker.SetPosition(*p)
        self.marker.SetVisibility(True)
        return True

    def move(self, x, y):
        if not self.dragging:
            return
        p = self._world(x, y)
        self.session.drag(p)
        if self.baseline is not None:
            self.baseline.drag(p)
        self.marker.SetPosition(*p)

    def release(self):
        if not self.dragging:
            return
        self.dragging = False
        self.session.release()
        if self.baseline is not None:
            self.baseline.release()
        self.marker.SetVisibility(False)

    def key(self, k):
        if k == "space":
            self.paused = not self.paused
        elif k == "r":
            self.release()
            self.session.reset()
            if self.baseline is not None:
                self.baseline.reset()
        elif k == "m":
            self.show_mesh = not self.show_mesh
            self.mesh_actor.SetVisibility(self.show_mesh)
        elif k == "b":
            self.toggle_baseline()
        self._update_text()

    def toggle_baseline(self):
        if self.baseline_factory is None:
            return
        if self.baseline is None:
            self.baseline = self.baseline_factory()
            self.base_actor = self.pl.add_mesh(
                self.baseline.surface, color="#9fb8c8", smooth_shading=True, name="baseline"
            )
            self.base_actor.mapper.SetInputData(self.baseline.surface)
            self.base_actor.SetPosition(self.offset, 0.0, 0.0)
            self.base_label = self.pl.add_text(
                "left: tet10 + normal-offset | right: tet4 + barycentric",
                position="upper_right",
                font_size=9,
                name="baseline_label",
            )
            self.show_baseline = True
        else:
            self.show_baseline = not self.show_baseline
        self.base_actor.SetVisibility(self.show_baseline)
        self.base_label.SetVisibility(self.show_baseline)
        self.pl.reset_camera()

    def tick(self):
        """One frame: step the session(s) unless paused, then render."""
        if not self.paused:
            t0 = time.perf_counter()
            self.stages = self.session.step()
            if self.baseline is not None and self.show_baseline:
                self.baseline.step()
            self.frame_ms = 1e3 * (time.perf_counter() - t0)
        self._update_text()
        self.pl.render()

    def _update_text(self):
        s = self.session
        state = "paused" if self.paused else "running"
        stages = " + ".join(f"{k} {1e3 * v:.1f}" for k, v in self.stages.items())
        self.status = (
            f"t = {s.time:.2f} s ({state})   frame {self.frame_ms:.1f} ms"
            + (f" ({stages} ms)" if stages else "")
            + f"\n{s.surface.n_points} surface vertices, {s.fe_rest.n_cells} "
            f"{s.kind} elements"
        )
        self.text.SetText(2, self.status)  # the upper left corner

    # -- wiring to VTK's interactor ---------------------------------------------------
    def connect(self):
        """Observe the interactor style's mouse events and the keys; a repeating timer
        drives tick()."""
        iren = self.pl.iren.interactor
        style = iren.GetInteractorStyle()
        # Observers on the style replace its own On...() handlers (vtkInteractorStyle
        # forwards an event to its observers instead, when it has any); pyvista's style
        # already observes the button events to call them itself. Ours run first
        # (priority 1) and abort the event when they handle it (a drag), else leave it
        # to pyvista's observer or, when there is none, call the style's handler.
        tags = {}

        def observe(event, handle, default):
            had = style.HasObserver(event)

            def callback(obj, ev):
                if handle():
                    style.GetCommand(tags[event]).SetAbortFlag(1)
                elif not had:
                    default()

            tags[event] = style.AddObserver(event, callback, 1.0)

        def on_press():
            return self.press(*iren.GetEventPosition())

        def on_move():
            if self.dragging:
                self.move(*iren.GetEventPosition())
            return self.dragging

        def on_release():
            was = self.dragging
            self.release()
            return was

        observe("LeftButtonPressEvent", on_press, style.OnLeftButtonDown)
        observe("MouseMoveEvent", on_move, style.OnMouseMove)
        observe("LeftButtonReleaseEvent", on_release, style.OnLeftButtonUp)
        for k in ("space", "r", "m", "b"):
            self.pl.add_key_event(k, lambda k=k: self.key(k))
        iren.AddObserver("TimerEvent", lambda o, e: self.tick())
        return iren

    def run(self, interval_ms=1):
        """Open the window and loop until it is closed."""
        self.pl.show(interactive_update=True, auto_close=False)
        iren = self.connect()
        iren.CreateRepeatingTimer(int(interval_ms))
        iren.Start()


def _report(label):
    last = [-1]

    def progress(f):
        pct = int(100 * f)
        if pct >= last[0] + 10 or f >= 1.0 and last[0] < 100:
            last[0] = pct
            print(f"\r{label}: {pct:3d}%", end="\n" if f >= 1.0 else "", flush=True)

    return progress


def prepare(surface=None, n_elements=_N_ELEMENTS, progress=True, order=2):
    """Mesh and embed a surface (the built-in thorny tail when None), printing progress.
    Returns (surface, fe_mesh, embedded, clamp mask)."""
    import hoembed

    builtin = surface is None
    if builtin:
        surface = hoembed.thorny_tail()
    kind = "tet10" if order == 2 else "tet4"
    method = "normal-offset" if order == 2 else "barycentric"
    fe = hoembed.tet10_mesh(
        surface,
        n_elements=n_elements,
        order=order,
        progress=_report(f"{kind} mesh") if progress else None,
    )
    emb = hoembed.embed(
        surface, fe, method=method, progress=_report(f"embedding ({method})") if progress else None
    )
    return surface, fe, emb, default_clamp(fe, builtin)


def live(surface=None, n_elements=_N_ELEMENTS, plotter=None, run=True, **session_options):
    """Open the live window on a surface (pyvista.PolyData, a file name, or None for the
    built-in thorny tail). Returns the LiveApp (after the window closes when `run`)."""
    if isinstance(surface, str):
        surface = pyvista.read(surface)
        if not isinstance(surface, pyvista.PolyData):
            surface = surface.extract_surface()
    surf, fe, emb, clamp = prepare(surface, n_elements)
    session = LiveSession(fe, emb, fixed=clamp, **session_options)

    def baseline():
        _, fe4, emb4, clamp4 = prepare(surf, max(4 * n_elements, 50), order=1)
        options = dict(session_options)
        # the same grab (radius, speed) as the tet10 model, whose cells are larger
        options.setdefault("grab_radius", session.grab_radius)
        options.setdefault("speed_limit", session.stepper.prescribed_speed_limit)
        return LiveSession(fe4, emb4, fixed=clamp4, **options)

    app = LiveApp(session, plotter=plotter, baseline=baseline)
    if run:
        app.run()
    return app


def run_cli(args):
    """``hoembed live [SURFACE]`` (hoembed.cli): read the file the way ``hoembed run``
    does (in a child process), then open the window."""
    import sys

    from . import cli

    try:
        if args.elements < 4:
            raise cli.UsageError("--elements must be at least 4")
        if not (args.young > 0 and np.isfinite(args.young)):
            raise cli.UsageError("--young must be > 0")
        if not np.all(np.isfinite(args.gravity)):
            raise cli.UsageError("--gravity must be finite")
        surface = None if args.surface is None else cli._read_surface(args.surface)
        options = {} if args.material is None else {"material": args.material}
        live(
            surface,
            n_elements=args.elements,
            young=args.young,
            gravity=tuple(args.gravity),
            **options,
        )
    except (cli.UsageError, HOEmbedError, OSError) as err:
        print(f"hoembed live: error: {err}", file=sys.stderr)
        return 2
    return 0
