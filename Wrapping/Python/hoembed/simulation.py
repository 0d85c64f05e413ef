"""pyvista-level front end of vtkCorotationalFEMStepper."""

import numpy as np
import pyvista
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

__all__ = ["simulate"]

from ._errors import (HOEmbedArgumentError, check_callable, check_dataset, check_int,
                      check_real, check_vector, run_filter)
from .hoembedFiltersSimulation import vtkCorotationalFEMStepper


def _vector_array(mesh, name, values, what):
    try:
        values = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise HOEmbedArgumentError(f"simulate: {what} must be numbers") from None
    if values.shape != (mesh.n_points, 3):
        raise HOEmbedArgumentError(
            f"simulate: {what} must have shape ({mesh.n_points}, 3), got {values.shape}")
    if not np.all(np.isfinite(values)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(values), axis=1))[0])
        raise HOEmbedArgumentError(f"simulate: {what} is not finite at node {bad}")
    mesh.point_data[name] = values


def _check_arguments(fe_mesh, steps, dt, young, poisson, density, gravity, rayleigh_mass,
                     rayleigh_stiffness, every, solver_tolerance, progress):
    """Refuse what vtkCorotationalFEMStepper would clamp, or accept as NaN. Each message
    names the argument and the stepper property it sets."""
    f = "simulate"
    check_dataset(f, "fe_mesh", fe_mesh, "vtkUnstructuredGrid")
    return dict(
        steps=check_int(f, "steps (NumberOfTimeSteps)", steps, 0),
        dt=check_real(f, "dt (TimeStep)", dt, 0.0, low_open=True),
        young=check_real(f, "young (YoungModulus)", young, 0.0, low_open=True),
        poisson=check_real(f, "poisson (PoissonRatio)", poisson, -1.0, 0.5, True, True),
        density=check_real(f, "density (Density)", density, 0.0, low_open=True),
        gravity=check_vector(f, "gravity (Gravity)", gravity),
        rayleigh_mass=check_real(f, "rayleigh_mass (RayleighMass)", rayleigh_mass, 0.0),
        rayleigh_stiffness=check_real(f, "rayleigh_stiffness (RayleighStiffness)",
                                      rayleigh_stiffness, 0.0),
        every=check_int(f, "every", every, 1),
        solver_tolerance=check_real(f, "solver_tolerance (SolverTolerance)", solver_tolerance,
                                    1e-16, 1.0),
        progress=check_callable(f, "progress", progress))


def simulate(fe_mesh, steps=100, dt=0.01, young=1.0e5, poisson=0.49, density=1000.0,
             gravity=(0.0, 0.0, -9.81), fixed=None, rayleigh_mass=0.1,
             rayleigh_stiffness=0.01, external_force=None, initial_displacement=None,
             initial_velocity=None, lumped_mass=False, static=False, every=1,
             solver_tolerance=1e-4, progress=None):
    """Simulate a co-rotated tet10 (or tet4) FE mesh with implicit Euler steps.

    Parameters
    ----------
    fe_mesh : pyvista.UnstructuredGrid
        Rest mesh of VTK_QUADRATIC_TETRA (or VTK_TETRA) cells. A point array ``Fixed``
        (nonzero = clamped) on it is honoured.
    steps, dt : int, float
        Number of time steps and their length (s). Frames are returned for
        t = 0, every*dt, 2*every*dt, ..., steps*dt (the first frame is the initial state).
    young, poisson, density : float
        Young's modulus (Pa, > 0), Poisson's ratio (in (-1, 0.5), default 0.49) and
        density (kg/m^3, > 0).
    gravity : 3 floats
        Gravity acceleration (default (0, 0, -9.81)).
    fixed : None, array, str or dict
        Clamped nodes: a boolean / integer mask of length n_points, the name of a point
        array, ``{"plane": (origin, normal)}`` (nodes with (x - origin) . normal <= 0)
        or ``{"box": (xmin, xmax, ymin, ymax, zmin, zmax)}``; None uses the mesh's own
        ``Fixed`` array if any.
    rayleigh_mass, rayleigh_stiffness : float
        Rayleigh damping C = a M + b K (defaults 0.1 and 0.01).
    external_force, initial_displacement, initial_velocity : (n_points, 3) arrays
        Optional nodal forces (N) and initial state.
    lumped_mass : bool
        HRZ-lumped mass instead of the consistent mass.
    static : bool
        Return the static equilibrium (one frame) instead of a time series.
    every : int
        Keep every ``every``-th step as a frame.
    progress : callable, optional
        Called with (frame index, number of frames) after each frame.

    Returns
    -------
    list of pyvista.UnstructuredGrid
        Deformed meshes with point data ``Displacement``, ``Velocity``, ``NodalRotation``,
        cell data ``VonMisesStress`` and field data ``TimeValue``.

    Raises
    ------
    hoembed.HOEmbedError
        On bad input (cells, clamps, non-finite state during integration). Bad arguments
        (a non-positive or NaN ``dt``, ``young`` or ``density``, ``poisson`` outside
        (-1, 0.5), negative ``steps``, ``every`` < 1, non-finite gravity, forces or initial
        state, a mask of the wrong length) raise ``hoembed._errors.HOEmbedArgumentError``
        (a HOEmbedError and a ValueError) before the stepper runs.

    Examples
    --------
    >>> frames = hoembed.simulate(mesh, steps=50, dt=0.01, young=5e4,
    ...                           fixed={"plane": ((0, 0, 0), (1, 0, 0))})
    """
    a = _check_arguments(fe_mesh, steps, dt, young, poisson, density, gravity, rayleigh_mass,
                         rayleigh_stiffness, every, solver_tolerance, progress)
    steps, dt, every = a["steps"], a["dt"], a["every"]
    mesh = pyvista.wrap(fe_mesh).copy(deep=False)
    alg = vtkCorotationalFEMStepper()
    if fixed is not None:
        if isinstance(fixed, str):
            alg.SetFixedArrayName(fixed)
        elif isinstance(fixed, dict):
            unknown = set(fixed) - {"plane", "box"}
            if unknown or not fixed:
                raise HOEmbedArgumentError("simulate: fixed dict needs a 'plane' or 'box' "
                                           f"entry (unknown keys: {sorted(map(str, unknown))})")
            if "plane" in fixed:
                try:
                    origin, normal = fixed["plane"]
                except (TypeError, ValueError):
                    raise HOEmbedArgumentError(
                        "simulate: fixed['plane'] must be (origin, normal)") from None
                origin = check_vector("simulate", "fixed['plane'] origin", origin)
                normal = check_vector("simulate", "fixed['plane'] normal", normal)
                if not any(normal):
                    raise HOEmbedArgumentError("simulate: fixed['plane'] normal is zero")
                alg.SetUseClampPlane(True)
                alg.SetClampPlaneOrigin(*origin)
                alg.SetClampPlaneNormal(*normal)
            if "box" in fixed:
                box = check_vector("simulate", "fixed['box']", fixed["box"], 6)
                if box[0] > box[1] or box[2] > box[3] or box[4] > box[5]:
                    raise HOEmbedArgumentError("simulate: fixed['box'] must be (xmin, xmax, "
                                               f"ymin, ymax, zmin, zmax), got {box}")
                alg.SetUseClampBox(True)
                alg.SetClampBox(*box)
        else:
            try:
                mask = np.asarray(fixed, dtype=float).reshape(-1)
            except (TypeError, ValueError):
                raise HOEmbedArgumentError("simulate: fixed must be a mask, an array name or "
                                           "a dict") from None
            if mask.shape[0] != mesh.n_points:
                raise HOEmbedArgumentError(
                    f"simulate: fixed mask must have {mesh.n_points} entries, "
                    f"got {mask.shape[0]}")
            if not np.all(np.isfinite(mask)):
                raise HOEmbedArgumentError("simulate: fixed mask holds NaN or Inf")
            mesh.point_data["Fixed"] = (mask != 0).astype(np.uint8)
            alg.SetFixedArrayName("Fixed")
    if external_force is not None:
        _vector_array(mesh, "ExternalForce", external_force, "external_force")
        alg.SetExternalForceArrayName("ExternalForce")
    if initial_displacement is not None:
        _vector_array(mesh, "InitialDisplacement", initial_displacement, "initial_displacement")
        alg.SetInitialDisplacementArrayName("InitialDisplacement")
    if initial_velocity is not None:
        _vector_array(mesh, "InitialVelocity", initial_velocity, "initial_velocity")
        alg.SetInitialVelocityArrayName("InitialVelocity")
    alg.SetInputData(mesh)
    alg.SetYoungModulus(a["young"])
    alg.SetPoissonRatio(a["poisson"])
    alg.SetDensity(a["density"])
    alg.SetGravity(*a["gravity"])
    alg.SetRayleighMass(a["rayleigh_mass"])
    alg.SetRayleighStiffness(a["rayleigh_stiffness"])
    alg.SetTimeStep(dt)
    alg.SetNumberOfTimeSteps(steps)
    alg.SetLumpedMass(bool(lumped_mass))
    alg.SetStaticSolve(bool(static))
    alg.SetSolverTolerance(a["solver_tolerance"])
    ks = [0] if static else list(range(0, steps + 1, every))
    if not static and ks[-1] != steps:
        ks.append(steps)
    frames = []
    for i, k in enumerate(ks):
        alg.UpdateInformation()
        alg.GetOutputInformation(0).Set(vtkStreamingDemandDrivenPipeline.UPDATE_TIME_STEP(),
                                        k * dt)
        out = pyvista.wrap(run_filter(alg)).copy()
        out.field_data["TimeValue"] = np.array([0.0 if static else k * dt])
        for name in ("ExternalForce", "InitialDisplacement", "InitialVelocity"):
            if name in out.point_data and name not in fe_mesh.point_data:
                del out.point_data[name]
        frames.append(out)
        if progress is not None:
            progress(i + 1, len(ks))
    return frames
