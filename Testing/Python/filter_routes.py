"""The pyvista-level functions' work done by the VTK build's wrapped filters instead
(vtkTet10Mesher, vtkEmbeddingCoordinatesFilter, vtkDeformationTransferFilter,
vtkCorotationalFEMStepper, vtkTimeSeriesWriter), for the tests that compare the two routes
(test_two_routes.py) and for the pip wheel's references (Testing/Pip/generate_reference.py).

The package's functions run the compiled drivers through hoembed._hoembed; the filters run
the same drivers from C++. This file only sets the filters' properties from the functions'
arguments (checked by the same hoembed._checks functions) and runs them: no rule here.
"""

import hoembed
import numpy as np
import pyvista
from hoembed._checks import (
    embed_arguments,
    mesh_arguments,
    point_normals_argument,
    simulate_arguments,
    simulate_clamps,
    simulate_frames,
    simulate_prescribed,
    simulate_vector,
    transfer_arguments,
)
from hoembed._errors import HOEmbedError, run_filter
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline


def tet10_mesh(
    surface,
    n_elements=1000,
    edge_length=0.0,
    order=2,
    curve_boundary=True,
    radius_edge_ratio=1.5,
    min_dihedral_angle=10.0,
    quality_target=0.2,
    minimum_quality=0.05,
):
    options = mesh_arguments(
        surface,
        n_elements,
        edge_length,
        order,
        curve_boundary,
        radius_edge_ratio,
        min_dihedral_angle,
        None,
        quality_target,
        minimum_quality,
    )
    alg = hoembed.vtkTet10Mesher()
    alg.SetInputData(surface)
    for name, value in options.items():
        getattr(alg, "Set" + name)(value)
    return pyvista.wrap(run_filter(alg)).copy()


def embed(surface, fe_mesh, method="normal-offset", n_partitions=0, warnings=None):
    method_value, n_partitions = embed_arguments(surface, fe_mesh, method, n_partitions, None)
    alg = hoembed.vtkEmbeddingCoordinatesFilter()
    alg.SetInputData(0, surface)
    alg.SetMeshData(fe_mesh)
    alg.SetMethod(method_value)
    alg.SetNumberOfPartitions(n_partitions)
    return pyvista.wrap(run_filter(alg, warnings=warnings)).copy()


def transfer(
    embedded_surface, deformed_mesh, normals="recompute", compute_point_normals=False, warnings=None
):
    mode = transfer_arguments(embedded_surface, deformed_mesh, normals)
    alg = hoembed.vtkDeformationTransferFilter()
    alg.SetInputData(0, embedded_surface)
    alg.SetInputData(1, deformed_mesh)
    alg.SetNormalMode(mode)
    pn_mode = point_normals_argument("transfer", compute_point_normals, "recompute")
    alg.SetComputePointNormals(pn_mode is not None)
    if pn_mode is not None:
        alg.SetPointNormalsMode(pn_mode)
    return pyvista.wrap(run_filter(alg, warnings=warnings)).copy()


def simulate(
    fe_mesh,
    steps=100,
    dt=0.01,
    young=1.0e5,
    poisson=0.49,
    density=1000.0,
    gravity=(0.0, 0.0, -9.81),
    fixed=None,
    rayleigh_mass=0.1,
    rayleigh_stiffness=0.01,
    external_force=None,
    initial_displacement=None,
    initial_velocity=None,
    lumped_mass=False,
    static=False,
    every=1,
    solver_tolerance=1e-4,
    prescribed=None,
    prescribed_speed_limit=0.0,
):
    a = simulate_arguments(
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
        None,
    )
    steps, dt, every = a["steps"], a["dt"], a["every"]
    mesh = pyvista.wrap(fe_mesh).copy(deep=False)
    alg = hoembed.vtkCorotationalFEMStepper()
    mask, targets, speed = simulate_prescribed(prescribed, prescribed_speed_limit, mesh.n_points)
    if mask is not None and not alg.SetPrescribedMotion(
        numpy_to_vtk(mask, deep=True), numpy_to_vtk(targets, deep=True)
    ):
        raise HOEmbedError("vtkCorotationalFEMStepper refused the prescribed motion")
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
    for value, name, setter in (
        (external_force, "ExternalForce", alg.SetExternalForceArrayName),
        (initial_displacement, "InitialDisplacement", alg.SetInitialDisplacementArrayName),
        (initial_velocity, "InitialVelocity", alg.SetInitialVelocityArrayName),
    ):
        if value is not None:
            mesh.point_data[name] = simulate_vector(mesh.n_points, value, name)
            setter(name)
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
    frames = []
    for k in simulate_frames(steps, every, static):
        alg.UpdateInformation()
        alg.GetOutputInformation(0).Set(vtkStreamingDemandDrivenPipeline.UPDATE_TIME_STEP(), k * dt)
        out = pyvista.wrap(run_filter(alg)).copy()
        out.field_data["TimeValue"] = np.array([0.0 if static else k * dt])
        for name in ("ExternalForce", "InitialDisplacement", "InitialVelocity"):
            if name in out.point_data and name not in fe_mesh.point_data:
                del out.point_data[name]
        frames.append(out)
    return frames
