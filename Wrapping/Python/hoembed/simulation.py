"""pyvista-level front end of vtkCorotationalFEMStepper."""

import numpy as np
import pyvista
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

__all__ = ["simulate"]

from ._checks import (SIMULATE_DOC, simulate_arguments, simulate_clamps, simulate_frames,
                      simulate_prescribed, simulate_vector)
from ._errors import HOEmbedError, run_filter
from .hoembedFiltersSimulation import vtkCorotationalFEMStepper


def simulate(fe_mesh, steps=100, dt=0.01, young=1.0e5, poisson=0.49, density=1000.0,
             gravity=(0.0, 0.0, -9.81), fixed=None, rayleigh_mass=0.1,
             rayleigh_stiffness=0.01, external_force=None, initial_displacement=None,
             initial_velocity=None, lumped_mass=False, static=False, every=1,
             solver_tolerance=1e-4, progress=None, prescribed=None,
             prescribed_speed_limit=0.0):
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


simulate.__doc__ = SIMULATE_DOC
