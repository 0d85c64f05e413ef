"""pyvista-level simulate() of the pip package: hoembed::StepperDriver through _hoembed.

The same arguments (prescribed motion included), docstring (shared in _checks.py), frames
and errors as the VTK build's hoembed.simulate (which runs vtkCorotationalFEMStepper over
the same driver). Reading the clamps' point array is the binding's part, as in the filter
(its messages are the filter's); the frame's arrays are written as the filter's
WriteOutput writes them."""
import numpy as np
import pyvista
from vtkmodules.vtkCommonCore import VTK_DOUBLE

from . import _arrays
from ._checks import (SIMULATE_DOC, simulate_arguments, simulate_clamps, simulate_frames,
                      simulate_prescribed, simulate_vector)
from ._errors import HOEmbedError
from ._hoembed import StepperDriver

__all__ = ["simulate"]


def _fail(message):
    raise HOEmbedError(f"simulate: {message}")


def _fixed_values(mesh, name):
    """vtkCorotationalFEMStepper::SetupClamps's reading of FixedArrayName: component 0 of
    a numeric point array as float64, or None when the default "Fixed" is absent."""
    pd = mesh.GetPointData()
    a = pd.GetArray(name)
    if a is None:
        if pd.GetAbstractArray(name) is not None:
            _fail(f"FixedArrayName '{name}' is a point-data array that is not numeric (e.g. "
                  "strings): the clamps need numbers (nonzero = clamped).")
        if mesh.GetCellData().GetAbstractArray(name) is not None or \
                mesh.GetFieldData().GetAbstractArray(name) is not None:
            _fail(f"FixedArrayName '{name}' is cell or field data, not point data: the clamps "
                  "are per node (nonzero = clamped).")
        if name != "Fixed":
            _fail(f"FixedArrayName '{name}' is not a point-data array of the input.")
        return None
    if a.GetNumberOfTuples() != mesh.GetNumberOfPoints():
        _fail(f"FixedArrayName '{name}' has {a.GetNumberOfTuples()} tuples, expected "
              f"{mesh.GetNumberOfPoints()} (one per point).")
    values = _arrays.vtk_to_numpy(a).reshape(a.GetNumberOfTuples(), -1)[:, 0]
    return np.ascontiguousarray(values, dtype=np.float64)


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
    mesh = pyvista.wrap(fe_mesh)
    prescribed_mask, prescribed_u, speed = simulate_prescribed(
        prescribed, prescribed_speed_limit, mesh.n_points)
    clamps = simulate_clamps(fixed, mesh.n_points)
    vectors = {}
    for key, value in (("external_force", external_force),
                       ("initial_displacement", initial_displacement),
                       ("initial_velocity", initial_velocity)):
        vectors[key] = None if value is None else simulate_vector(mesh.n_points, value, key)
    if mesh.GetNumberOfCells() == 0 or mesh.GetPoints() is None:
        _fail("The input mesh is empty (no cells).")
    if clamps["mask"] is not None:
        fixed_values = clamps["mask"].astype(np.float64)
    else:
        fixed_values = _fixed_values(mesh, clamps["name"] or "Fixed")
    plane = () if clamps["plane"] is None else tuple(clamps["plane"][0]) + \
        tuple(clamps["plane"][1])
    box = () if clamps["box"] is None else tuple(clamps["box"])
    offsets, conn = _arrays.cells(mesh.GetCells())
    types = np.ascontiguousarray(_arrays.vtk_to_numpy(_arrays.cell_types(mesh)),
                                 dtype=np.uint8)
    driver = StepperDriver()
    try:
        driver.build(mesh.GetNumberOfPoints(), _arrays.points(mesh.GetPoints()), types,
                     offsets, conn,
                     [a["young"], a["poisson"], a["density"], dt, a["rayleigh_mass"],
                      a["rayleigh_stiffness"], a["solver_tolerance"]],
                     bool(lumped_mass), bool(static), list(a["gravity"]), list(plane),
                     list(box), fixed_values,
                     *(None if v is None else v.reshape(-1) for v in vectors.values()),
                     prescribed_mask=None if prescribed_mask is None else
                     prescribed_mask.astype(np.float64),
                     prescribed_displacement=None if prescribed_u is None else
                     np.ascontiguousarray(prescribed_u, dtype=np.float64).reshape(-1),
                     prescribed_speed_limit=speed)
    except RuntimeError as e:
        _fail(e)
    n, nc = mesh.n_points, mesh.n_cells
    # the input's structure, point and cell data (as the filter's CopyStructure and
    # PassData); no field data but the stepper's
    rest = mesh.copy()
    rest.field_data.clear()
    if clamps["mask"] is not None:
        rest.point_data["Fixed"] = clamps["mask"]
    ks = simulate_frames(steps, every, static)
    frames = []
    for i, k in enumerate(ks):
        try:
            driver.advance(k)
        except RuntimeError as e:
            _fail(e)
        x, disp, vel = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
        rot, vm = np.empty((n, 9)), np.empty(nc)
        kinetic, strain, iterations = driver.write_frame(x, disp, vel, rot, vm)
        out = rest.copy()
        out.points = x
        out.point_data["Displacement"] = disp
        out.point_data["Velocity"] = vel
        out.point_data["NodalRotation"] = rot
        out.cell_data["VonMisesStress"] = vm
        out.field_data["KineticEnergy"] = np.array([kinetic])
        out.field_data["StrainEnergy"] = np.array([strain])
        out.field_data["SolverIterations"] = np.array([float(iterations)])
        out.field_data["TimeValue"] = np.array([0.0 if static else k * dt])
        frames.append(out)
        if progress is not None:
            progress(i + 1, len(ks))
    return frames


simulate.__doc__ = SIMULATE_DOC
