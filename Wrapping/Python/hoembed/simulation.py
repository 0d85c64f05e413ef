"""pyvista-level front end of vtkCorotationalFEMStepper."""

import numpy as np
import pyvista
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

__all__ = ["simulate"]

from ._checks import (simulate_arguments, simulate_clamps, simulate_frames,
                      simulate_prescribed, simulate_vector)
from ._errors import HOEmbedError, run_filter
from .hoembedFiltersSimulation import vtkCorotationalFEMStepper


def simulate(fe_mesh, steps=100, dt=0.01, young=1.0e5, poisson=0.49, density=1000.0,
             gravity=(0.0, 0.0, -9.81), fixed=None, rayleigh_mass=0.1,
             rayleigh_stiffness=0.01, external_force=None, initial_displacement=None,
             initial_velocity=None, lumped_mass=False, static=False, every=1,
             solver_tolerance=1e-4, progress=None, prescribed=None,
             prescribed_speed_limit=0.0):
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
    prescribed : (mask, displacement), optional
        Prescribed motion (vtkCorotationalFEMStepper.SetPrescribedMotion): the nodes where
        ``mask`` (length n_points) is nonzero are hard Dirichlet nodes held at rest +
        ``displacement`` ((n_points, 3), or one 3-vector for all of them), reached in the
        first step (a velocity kick) or, with ``prescribed_speed_limit``, moved there at
        that speed. Clamped nodes stay clamped. With ``static``, the equilibrium with those
        nodes displaced.
    prescribed_speed_limit : float
        Distance per second the prescribed nodes move at most (0, default: no limit).
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
    a = simulate_arguments(fe_mesh, steps, dt, young, poisson, density, gravity,
                           rayleigh_mass, rayleigh_stiffness, every, solver_tolerance,
                           progress)
    steps, dt, every = a["steps"], a["dt"], a["every"]
    mesh = pyvista.wrap(fe_mesh).copy(deep=False)
    alg = vtkCorotationalFEMStepper()
    prescribed_mask, prescribed_u, speed = simulate_prescribed(
        prescribed, prescribed_speed_limit, mesh.n_points)
    if prescribed_mask is not None:
        if not alg.SetPrescribedMotion(numpy_to_vtk(prescribed_mask, deep=True),
                                       numpy_to_vtk(prescribed_u, deep=True)):
            raise HOEmbedError("simulate: vtkCorotationalFEMStepper refused the prescribed "
                               "motion")
    alg.SetPrescribedSpeedLimit(speed)
    clamps = simulate_clamps(fixed, mesh.n_points)
    if clamps["name"] is not None:
        alg.SetFixedArrayName(clamps["name"])
    if clamps["plane"] is not None:
        alg.SetUseClampPlane(True)
        alg.SetClampPlaneOrigin(*clamps["plane"][0])
        alg.SetClampPlaneNormal(*clamps["plane"][1])
    if clamps["box"] is not None:
        alg.SetUseClampBox(True)
        alg.SetClampBox(*clamps["box"])
    if clamps["mask"] is not None:
        mesh.point_data["Fixed"] = clamps["mask"]
        alg.SetFixedArrayName("Fixed")
    if external_force is not None:
        mesh.point_data["ExternalForce"] = simulate_vector(mesh.n_points, external_force,
                                                           "external_force")
        alg.SetExternalForceArrayName("ExternalForce")
    if initial_displacement is not None:
        mesh.point_data["InitialDisplacement"] = simulate_vector(
            mesh.n_points, initial_displacement, "initial_displacement")
        alg.SetInitialDisplacementArrayName("InitialDisplacement")
    if initial_velocity is not None:
        mesh.point_data["InitialVelocity"] = simulate_vector(mesh.n_points, initial_velocity,
                                                             "initial_velocity")
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
    ks = simulate_frames(steps, every, static)
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
