"""Argument checks of the pyvista-level tet10_mesh(), embed(), transfer(), simulate()
and write_series() (meshing.py, embedding.py, transfer.py, simulation.py, series.py),
before any driver runs. Pure Python."""

import numpy as np

from ._arrays import N
from ._errors import (
    HOEmbedArgumentError,
    HOEmbedError,
    check_callable,
    check_dataset,
    check_int,
    check_real,
    check_vector,
)
from ._hoembed import DEFAULTS, check_range

# values of hoembed::EmbeddingMethod (= vtkEmbeddingCoordinatesFilter's Method)
EMBED_METHODS = {"normal-offset": 0, "barycentric": 1}
# values of hoembed::TransferNormals (= vtkDeformationTransferFilter's NormalMode)
NORMAL_MODES = {"recompute": 0, "rotate": 1, "deform": 2}
# vtkDeformationTransferFilter's PointNormalsMode (the driver's TransferPointNormals)
POINT_NORMALS_MODES = {"recompute": 0, "transform": 1}
# the names of those values (the functions' keyword defaults name the drivers' defaults)
EMBED_METHOD_NAMES = {v: k for k, v in EMBED_METHODS.items()}
NORMAL_MODE_NAMES = {v: k for k, v in NORMAL_MODES.items()}
POINT_NORMALS_MODE_NAMES = {v: k for k, v in POINT_NORMALS_MODES.items()}


def point_normals_argument(who, value, default):
    """The TransferPointNormals value of a point_normals argument, or None (no normals):
    "transform", "recompute", False, or True (= `default`, the caller's mode)."""
    if value is False or value is None:
        return None
    if value is True:
        value = default
    if not isinstance(value, str) or value not in POINT_NORMALS_MODES:
        raise HOEmbedArgumentError(
            f"{who}: point_normals must be 'transform', 'recompute', True or False, not {value!r}"
        )
    return POINT_NORMALS_MODES[value]


# tet10_mesh()'s docstring, the same in both packages (the wheel appends how its VTK
# steps run)
MESH_DOC = """Mesh any triangle surface with coarse, curved, valid tet10 (or tet4) elements.

Parameters
----------
surface : pyvista.PolyData or vtkPolyData
    Any triangle surface: closed or open, one or several parts, non-manifold or
    self-intersecting (polygons and strips are triangulated). A surface that is not
    a clean closed manifold is meshed through its envelope (vtkTet10Mesher's
    EnvelopeTolerance; field data ``EnvelopeOffset``, ``EnvelopeNodeCount``).
n_elements : int
    Approximate number of elements (default <TargetNumberOfElements>); ignored if
    ``edge_length > 0``.
edge_length : float
    Target edge length in surface units (default <TargetEdgeLength>; 0: from
    ``n_elements``).
order : int
    2 for VTK_QUADRATIC_TETRA, 1 for VTK_TETRA (default <ElementOrder>).
curve_boundary : bool
    Move boundary mid-edge nodes onto the surface (default <CurveBoundary>).
radius_edge_ratio, min_dihedral_angle : float
    TetGen quality bounds (defaults <RadiusEdgeRatio> and <MinDihedralAngle> degrees).
quality_target : float
    Curving never takes an element below min(quality_target, its straight shape's
    minimum scaled Jacobian) (default <CurvedQualityTarget>).
minimum_quality : float
    The floor of every element's minimum scaled Jacobian (default <MinimumQuality>);
    elements below it are counted (field data ``PoorElementCount``) and named in a
    warning with the element count that would lift them.
progress : callable, optional
    Called with a float in [0, 1] on the filter's progress events.

Returns
-------
pyvista.UnstructuredGrid
    With cell data ``MinScaledJacobian`` and field data ``RelaxedNodeCount``,
    ``CurvedNodeCount``, ``EnvelopeNodeCount``, ``BoundaryCrossingsFound``,
    ``BoundaryCrossingsLeft``, ``MaxSurfaceDeviation`` and ``EnvelopeOffset``.

Raises
------
hoembed.HOEmbedError
    On bad input (empty, NaN, point ids out of range, no polygons, no triangle with
    an area), a TetGen failure, or a mesh estimated beyond the element limit. Bad
    arguments (of the wrong type, a surface that is not poly data, or a value outside
    the mesher's range, ``hoembed._hoembed.RANGES["mesher"]``, refused with the mesher's
    sentence) raise ``hoembed._errors.HOEmbedArgumentError`` (a HOEmbedError and a
    ValueError) before the filter runs.

Examples
--------
>>> import pyvista as pv, hoembed
>>> mesh = hoembed.tet10_mesh(pv.Sphere(), n_elements=500)
"""


def _with_defaults(doc, defaults):
    """`doc` with each <Name> replaced by the driver's default of the property Name (the
    docstrings state the defaults without writing them again)."""
    for name, value in defaults.items():
        doc = doc.replace(f"<{name}>", repr(value))
    return doc


MESH_DOC = _with_defaults(MESH_DOC, DEFAULTS["mesher"])


def driver_ranges(func, driver, values):
    """Refuse a value outside its driver's range with the driver's sentence (hoembed::
    MesherRanges, StepperRanges through check_range), before any driver runs: `values` is
    {property: (argument name, value)}. Returns {property: value}."""
    for prop, (arg, value) in values.items():
        error = check_range(driver, prop, value)
        if error:
            raise HOEmbedArgumentError(f"{func}: {arg}: {error}")
    return {prop: value for prop, (_, value) in values.items()}


def mesh_arguments(
    surface,
    n_elements,
    edge_length,
    order,
    curve_boundary,
    radius_edge_ratio,
    min_dihedral_angle,
    progress,
    quality_target,
    minimum_quality,
):
    """Check tet10_mesh()'s arguments: their types here, their ranges by the mesher driver.
    Returns the vtkTet10Mesher properties they set."""
    f = "tet10_mesh"
    check_dataset(f, "surface", surface, "vtkPolyData")
    if not isinstance(curve_boundary, (bool, int)):
        raise HOEmbedArgumentError(f"{f}: curve_boundary must be True or False")
    check_callable(f, "progress", progress)
    props = driver_ranges(
        f,
        "mesher",
        dict(
            TargetNumberOfElements=("n_elements", check_int(f, "n_elements", n_elements)),
            TargetEdgeLength=(
                "edge_length",
                check_real(f, "edge_length", edge_length, finite=False),
            ),
            ElementOrder=("order", check_int(f, "order", order)),
            RadiusEdgeRatio=(
                "radius_edge_ratio",
                check_real(f, "radius_edge_ratio", radius_edge_ratio, finite=False),
            ),
            MinDihedralAngle=(
                "min_dihedral_angle",
                check_real(f, "min_dihedral_angle", min_dihedral_angle, finite=False),
            ),
            CurvedQualityTarget=(
                "quality_target",
                check_real(f, "quality_target", quality_target, finite=False),
            ),
            MinimumQuality=(
                "minimum_quality",
                check_real(f, "minimum_quality", minimum_quality, finite=False),
            ),
        ),
    )
    return dict(props, CurveBoundary=bool(curve_boundary))


def embed_arguments(surface, fe_mesh, method, n_partitions, progress):
    """Check embed()'s arguments; returns (method value, n_partitions as int)."""
    if not isinstance(method, str) or method not in EMBED_METHODS:
        raise HOEmbedArgumentError(
            f"embed: method must be one of {sorted(EMBED_METHODS)}, not {method!r}"
        )
    check_dataset("embed", "surface", surface, "vtkPolyData")
    check_dataset("embed", "fe_mesh", fe_mesh, "vtkUnstructuredGrid")
    n_partitions = driver_ranges(
        "embed",
        "embedding",
        dict(NumberOfPartitions=("n_partitions", check_int("embed", "n_partitions", n_partitions))),
    )["NumberOfPartitions"]
    check_callable("embed", "progress", progress)
    return EMBED_METHODS[method], n_partitions


def transfer_arguments(embedded_surface, deformed_mesh, normals):
    """Check transfer()'s arguments; returns the normal mode's value."""
    if not isinstance(normals, str) or normals not in NORMAL_MODES:
        raise HOEmbedArgumentError(
            f"transfer: normals must be 'recompute', 'rotate' or 'deform', not {normals!r}"
        )
    check_dataset("transfer", "embedded_surface", embedded_surface, "vtkPolyData")
    check_dataset("transfer", "deformed_mesh", deformed_mesh, "vtkUnstructuredGrid")
    return NORMAL_MODES[normals]


def simulate_arguments(
    fe_mesh,
    steps,
    dt,
    young,
    poisson,
    density,
    gravity,
    rayleigh_mass,
    rayleigh_stiffness,
    every,
    solver_tolerance,
    progress,
):
    """Their types here, their ranges by the stepper driver (its sentences name the
    stepper property each argument sets), before the stepper runs."""
    f = "simulate"
    check_dataset(f, "fe_mesh", fe_mesh, "vtkUnstructuredGrid")
    gravity = check_vector(f, "gravity (Gravity)", gravity)
    real = {
        "dt": ("TimeStep", dt),
        "young": ("YoungModulus", young),
        "poisson": ("PoissonRatio", poisson),
        "density": ("Density", density),
        "rayleigh_mass": ("RayleighMass", rayleigh_mass),
        "rayleigh_stiffness": ("RayleighStiffness", rayleigh_stiffness),
        "solver_tolerance": ("SolverTolerance", solver_tolerance),
    }
    values = {
        prop: (arg, check_real(f, arg, value, finite=False)) for arg, (prop, value) in real.items()
    }
    values["NumberOfTimeSteps"] = ("steps", check_int(f, "steps", steps))
    props = driver_ranges(f, "stepper", values)
    return dict(
        steps=props["NumberOfTimeSteps"],
        dt=props["TimeStep"],
        young=props["YoungModulus"],
        poisson=props["PoissonRatio"],
        density=props["Density"],
        gravity=gravity,
        rayleigh_mass=props["RayleighMass"],
        rayleigh_stiffness=props["RayleighStiffness"],
        every=check_int(f, "every", every, 1),  # simulate()'s own argument
        solver_tolerance=props["SolverTolerance"],
        progress=check_callable(f, "progress", progress),
    )


def simulate_vector(n_points, values, what):
    """An (n_points, 3) finite float64 array of simulate()'s per-node vectors."""
    try:
        values = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise HOEmbedArgumentError(f"simulate: {what} must be numbers") from None
    if values.shape != (n_points, 3):
        raise HOEmbedArgumentError(
            f"simulate: {what} must have shape ({n_points}, 3), got {values.shape}"
        )
    if not np.all(np.isfinite(values)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(values), axis=1))[0])
        raise HOEmbedArgumentError(f"simulate: {what} is not finite at node {bad}")
    return values


def simulate_prescribed(prescribed, speed_limit, n_points):
    """simulate()'s ``prescribed`` ((mask, displacement): None or a uint8 mask per node and
    an (n_points, 3) target displacement, a 3-vector being the same for every node) and
    ``prescribed_speed_limit`` (a finite number >= 0)."""
    try:
        speed_limit = float(speed_limit)
    except (TypeError, ValueError):
        raise HOEmbedArgumentError("simulate: prescribed_speed_limit must be a number") from None
    driver_ranges(
        "simulate", "stepper", dict(PrescribedSpeedLimit=("prescribed_speed_limit", speed_limit))
    )
    if prescribed is None:
        return None, None, speed_limit
    try:
        mask, displacement = prescribed
    except (TypeError, ValueError):
        raise HOEmbedArgumentError("simulate: prescribed must be (mask, displacement)") from None
    try:
        mask = np.asarray(mask, dtype=float)
    except (TypeError, ValueError):
        raise HOEmbedArgumentError("simulate: prescribed mask must be numbers") from None
    if mask.shape != (n_points,):
        raise HOEmbedArgumentError(
            f"simulate: prescribed mask must have {n_points} entries (one per node), "
            f"got shape {mask.shape}"
        )
    if not np.all(np.isfinite(mask)):
        raise HOEmbedArgumentError("simulate: prescribed mask holds NaN or Inf")
    try:
        d = np.asarray(displacement, dtype=float)
    except (TypeError, ValueError):
        raise HOEmbedArgumentError("simulate: prescribed displacement must be numbers") from None
    if d.shape == (3,):
        d = np.tile(d, (n_points, 1))
    d = simulate_vector(n_points, d, "prescribed displacement")
    return (mask != 0).astype(np.uint8), d, speed_limit


def simulate_clamps(fixed, n_points):
    """simulate()'s ``fixed``: a dict with "name" (a point array's name), "mask" (uint8
    per node), "plane" ((origin, normal)) and "box" (6 numbers), each None when not given."""
    out = dict(name=None, mask=None, plane=None, box=None)
    if fixed is None:
        return out
    if isinstance(fixed, str):
        out["name"] = fixed
    elif isinstance(fixed, dict):
        unknown = set(fixed) - {"plane", "box"}
        if unknown or not fixed:
            raise HOEmbedArgumentError(
                "simulate: fixed dict needs a 'plane' or 'box' "
                f"entry (unknown keys: {sorted(map(str, unknown))})"
            )
        if "plane" in fixed:
            try:
                origin, normal = fixed["plane"]
            except (TypeError, ValueError):
                raise HOEmbedArgumentError(
                    "simulate: fixed['plane'] must be (origin, normal)"
                ) from None
            origin = check_vector("simulate", "fixed['plane'] origin", origin)
            normal = check_vector("simulate", "fixed['plane'] normal", normal)
            if not any(normal):
                raise HOEmbedArgumentError("simulate: fixed['plane'] normal is zero")
            out["plane"] = (origin, normal)
        if "box" in fixed:
            box = check_vector("simulate", "fixed['box']", fixed["box"], 6)
            if box[0] > box[1] or box[2] > box[3] or box[4] > box[5]:
                raise HOEmbedArgumentError(
                    "simulate: fixed['box'] must be (xmin, xmax, "
                    f"ymin, ymax, zmin, zmax), got {box}"
                )
            out["box"] = box
    else:
        try:
            mask = np.asarray(fixed, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise HOEmbedArgumentError(
                "simulate: fixed must be a mask, an array name or a dict"
            ) from None
        if mask.shape[0] != n_points:
            raise HOEmbedArgumentError(
                f"simulate: fixed mask must have {n_points} entries, got {mask.shape[0]}"
            )
        if not np.all(np.isfinite(mask)):
            raise HOEmbedArgumentError("simulate: fixed mask holds NaN or Inf")
        out["mask"] = (mask != 0).astype(np.uint8)
    return out


def simulate_frames(steps, every, static):
    """The step indices simulate() returns frames of: 0, every, 2 every, ..., steps."""
    ks = [0] if static else list(range(0, steps + 1, every))
    if not static and ks[-1] != steps:
        ks.append(steps)
    return ks


# ---- simulate: one docstring for both bindings (the VTK build's simulation.py over
# vtkCorotationalFEMStepper, the wheel's over hoembed::StepperDriver)

SIMULATE_DOC = """Simulate a co-rotated tet10 (or tet4) FE mesh with implicit Euler steps.

    Parameters
    ----------
    fe_mesh : pyvista.UnstructuredGrid
        Rest mesh of VTK_QUADRATIC_TETRA (or VTK_TETRA) cells. A point array ``Fixed``
        (nonzero = clamped) on it is honoured.
    steps, dt : int, float
        Number of time steps and their length (s). Frames are returned for
        t = 0, every*dt, 2*every*dt, ..., steps*dt (the first frame is the initial state).
    young, poisson, density : float
        Young's modulus (Pa, > 0, default <YoungModulus>), Poisson's ratio (in (-1, 0.5),
        default <PoissonRatio>) and density (kg/m^3, > 0, default <Density>).
    gravity : 3 floats
        Gravity acceleration (default <Gravity>).
    fixed : None, array, str or dict
        Clamped nodes: a boolean / integer mask of length n_points, the name of a point
        array, ``{"plane": (origin, normal)}`` (nodes with (x - origin) . normal <= 0)
        or ``{"box": (xmin, xmax, ymin, ymax, zmin, zmax)}``; None uses the mesh's own
        ``Fixed`` array if any.
    rayleigh_mass, rayleigh_stiffness : float
        Rayleigh damping C = a M + b K (defaults <RayleighMass> and <RayleighStiffness>).
    external_force, initial_displacement, initial_velocity : (n_points, 3) arrays
        Optional nodal forces (N) and initial state.
    lumped_mass : bool
        HRZ-lumped mass instead of the consistent mass.
    prescribed : (mask, displacement), optional
        Prescribed motion (the stepper's SetPrescribedMotion): the nodes where
        ``mask`` (length n_points) is nonzero are hard Dirichlet nodes held at rest +
        ``displacement`` ((n_points, 3), or one 3-vector for all of them), reached in the
        first step (a velocity kick) or, with ``prescribed_speed_limit``, moved there at
        that speed. Clamped nodes stay clamped. With ``static``, the equilibrium with those
        nodes displaced.
    prescribed_speed_limit : float
        Distance per second the prescribed nodes move at most (default
        <PrescribedSpeedLimit>; 0: no limit).
    static : bool
        Return the static equilibrium (one frame) instead of a time series.
    material : str
        ``"corotated"`` (default: co-rotated linear elasticity), ``"stvk"``,
        ``"neo-hookean"`` (the stable Neo-Hookean of Smith et al. 2018, stable under
        inversion) or ``"mooney-rivlin"``: hyperelastic laws with constants from ``young``
        and ``poisson`` (their small-strain limit), stepped by Newton's method on the
        backward-Euler potential (the stepper's Material).
    mooney_rivlin : (C10, C01)
        Mooney-Rivlin's constants (Pa); (0, 0), the default: both mu / 4.
    newton_tolerance, max_newton_iterations : float, int
        Newton's stop rule for the hyperelastic laws (defaults 1e-8 and 50; 1 iteration:
        one linearised solve per step); a static solve fails when they do not suffice.
    every : int
        Keep every ``every``-th step as a frame.
    progress : callable, optional
        Called with (frame index, number of frames) after each frame.

    Returns
    -------
    list of pyvista.UnstructuredGrid
        Deformed meshes with point data ``Displacement``, ``Velocity``, ``NodalRotation``,
        cell data ``VonMisesStress`` and field data ``KineticEnergy``, ``StrainEnergy``,
        ``SolverIterations`` and ``TimeValue`` (the same in the VTK build and the pip
        wheel, bit for bit when the wheel's stepper kernels are compiled with the VTK
        build's flags).

    Raises
    ------
    hoembed.HOEmbedError
        On bad input (cells, clamps, non-finite state during integration, an unknown
        ``material``). Bad arguments (a value outside the stepper's range,
        ``hoembed._hoembed.RANGES["stepper"]``, e.g. a non-positive ``dt``, negative
        Mooney-Rivlin constants or bad Newton controls, refused with the stepper's sentence;
        ``every`` < 1, non-finite gravity, forces or initial state, a mask of the wrong
        length) raise ``hoembed._errors.HOEmbedArgumentError`` (a HOEmbedError and a
        ValueError) before the stepper runs.

    Examples
    --------
    >>> frames = hoembed.simulate(mesh, steps=50, dt=0.01, young=5e4,
    ...                           fixed={"plane": ((0, 0, 0), (1, 0, 0))})
    """

SIMULATE_DOC = _with_defaults(SIMULATE_DOC, DEFAULTS["stepper"])


# ---- write_series: one signature, docstring and set of argument checks for both bindings
# (the VTK build's series.py over vtkTimeSeriesWriter, the wheel's over SeriesFiles)

WRITE_SERIES_DOC = """Write a time series readable by ParaView and ``pyvista.read``.

    Parameters
    ----------
    frames_or_algorithm : sequence of datasets, or a vtkAlgorithm
        Either frames (pyvista / VTK unstructured grids or poly data; each frame's time is
        its field data ``TimeValue`` when present, else its index, unless ``times`` is
        given), or a VTK algorithm whose output is written over its advertised time steps
        (or ``times``).
    folder : str or path
        Output folder (created if needed).
    name : str
        Series name: writes ``folder/name.pvd`` and ``folder/name/name_NNNNNN.vt[up]``.
    times : sequence of float, optional
        Times of the frames / times to request from the algorithm.

    Returns
    -------
    str
        Path of the .pvd file.

    Raises
    ------
    hoembed.HOEmbedError
        If a frame has an unsupported type or a non-finite time, the input fails, or the
        folder or a file cannot be written. Nothing is half-written: the frames go to a
        staging folder and replace an older series of the same name only once all of
        them and the .pvd are complete; on failure the older series is left intact.
    """


def series_path(folder, name):
    """write_series()'s name and folder checked, the folder created; the .pvd path."""
    import os

    folder = os.fspath(folder)
    name = str(name)
    if not name or name.startswith(".") or os.sep in name or (os.altsep and os.altsep in name):
        raise HOEmbedError(
            f"write_series: the series name {name!r} must be a plain file "
            "name (no folder, not starting with '.')"
        )
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as err:
        raise HOEmbedError(
            f"write_series: cannot create the output folder {folder!r}: {err.strerror or err}"
        ) from None
    if not os.access(folder, os.W_OK | os.X_OK):
        raise HOEmbedError(f"write_series: the output folder {folder!r} is not writable")
    return os.path.join(folder, f"{name}.pvd")


def series_frame_times(frames, times):
    """The time of each frame: ``times`` (one per frame), else the frame's field data
    ``TimeValue`` when present, else its index."""
    if times is not None and len(times) != len(frames):
        raise ValueError("times must have one value per frame")
    out = []
    for i, frame in enumerate(frames):
        if times is not None:
            out.append(float(times[i]))
            continue
        fd = getattr(frame, "field_data", None)
        if fd is not None and N.TimeValue in fd and len(fd[N.TimeValue]):
            out.append(float(fd[N.TimeValue][0]))
        else:
            out.append(float(i))
    return out
