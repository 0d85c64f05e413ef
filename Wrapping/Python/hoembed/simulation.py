"""pyvista-level front end of vtkCorotationalFEMStepper."""

import numpy as np
import pyvista
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

__all__ = ["simulate"]

from ._errors import run_filter
from .hoembedFiltersSimulation import vtkCorotationalFEMStepper


def _vector_array(mesh, name, values, what):
    values = np.asarray(values, dtype=float)
    if values.shape != (mesh.n_points, 3):
        raise ValueError(f"{what} must have shape ({mesh.n_points}, 3), got {values.shape}")
    mesh.point_data[name] = values


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
        On bad input (material, time step, cells, non-finite state during integration).

    Examples
    --------
    >>> frames = hoembed.simulate(mesh, steps=50, dt=0.01, young=5e4,
    ...                           fixed={"plane": ((0, 0, 0), (1, 0, 0))})
    """
    mesh = pyvista.wrap(fe_mesh).copy(deep=False)
    alg = vtkCorotationalFEMStepper()
    if fixed is not None:
        if isinstance(fixed, str):
            alg.SetFixedArrayName(fixed)
        elif isinstance(fixed, dict):
            if "plane" in fixed:
                origin, normal = fixed["plane"]
                alg.SetUseClampPlane(True)
                alg.SetClampPlaneOrigin(*map(float, origin))
                alg.SetClampPlaneNormal(*map(float, normal))
            if "box" in fixed:
                alg.SetUseClampBox(True)
                alg.SetClampBox(*map(float, fixed["box"]))
            if not ({"plane", "box"} & set(fixed)):
                raise ValueError("fixed dict needs a 'plane' or 'box' entry")
        else:
            mask = np.asarray(fixed).reshape(-1)
            if mask.shape[0] != mesh.n_points:
                raise ValueError(f"fixed mask must have {mesh.n_points} entries")
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
    alg.SetYoungModulus(float(young))
    alg.SetPoissonRatio(float(poisson))
    alg.SetDensity(float(density))
    alg.SetGravity(*map(float, gravity))
    alg.SetRayleighMass(float(rayleigh_mass))
    alg.SetRayleighStiffness(float(rayleigh_stiffness))
    alg.SetTimeStep(float(dt))
    alg.SetNumberOfTimeSteps(int(steps))
    alg.SetLumpedMass(bool(lumped_mass))
    alg.SetStaticSolve(bool(static))
    alg.SetSolverTolerance(float(solver_tolerance))
    every = max(1, int(every))
    ks = [0] if static else list(range(0, int(steps) + 1, every))
    if not static and ks[-1] != int(steps):
        ks.append(int(steps))
    frames = []
    for i, k in enumerate(ks):
        alg.UpdateInformation()
        alg.GetOutputInformation(0).Set(vtkStreamingDemandDrivenPipeline.UPDATE_TIME_STEP(),
                                        k * float(dt))
        out = pyvista.wrap(run_filter(alg)).copy()
        out.field_data["TimeValue"] = np.array([0.0 if static else k * float(dt)])
        for name in ("ExternalForce", "InitialDisplacement", "InitialVelocity"):
            if name in out.point_data and name not in fe_mesh.point_data:
                del out.point_data[name]
        frames.append(out)
        if progress is not None:
            progress(i + 1, len(ks))
    return frames
