"""pyvista-level simulate(): hoembed::StepperDriver through _hoembed (the driver
vtkCorotationalFEMStepper runs: the same frames bit for bit, the same error sentences).
The frame's arrays are the driver's WriteFrame, as in the filter's output."""

import numpy as np
import pyvista

from . import _arrays
from ._arrays import N
from ._checks import (
    SIMULATE_DOC,
    simulate_arguments,
    simulate_clamps,
    simulate_frames,
    simulate_prescribed,
    simulate_vector,
)
from ._errors import HOEmbedError
from ._hoembed import DEFAULTS, MATERIALS, StepperDriver

__all__ = ["simulate"]
# the keyword defaults: vtkCorotationalFEMStepper's, which are the driver's
# (hoembed::StepperParameters, hoembed::StepperOptions)
_D = DEFAULTS["stepper"]


def _fail(message):
    raise HOEmbedError(f"simulate: {message}")


def _fixed_values(mesh, name):
    """The clamps' point array FixedArrayName, component 0 as float64 (None: none).
    Where the array is (numeric point data, other point data, cell or field data,
    nowhere) is read here; whether that is allowed is the driver's rule
    (StepperDriver::CheckFixedArray, as vtkCorotationalFEMStepper)."""
    pd = mesh.GetPointData()
    a = pd.GetArray(name)
    if a is not None:
        kind = "numeric"
    elif pd.GetAbstractArray(name) is not None:
        kind = "not numeric"
    elif (
        mesh.GetCellData().GetAbstractArray(name) is not None
        or mesh.GetFieldData().GetAbstractArray(name) is not None
    ):
        kind = "cell or field"
    else:
        kind = "absent"
    try:
        StepperDriver.check_fixed_array(
            name, kind, a.GetNumberOfTuples() if a else 0, mesh.GetNumberOfPoints()
        )
    except RuntimeError as e:
        _fail(e)
    if a is None:
        return None
    values = _arrays.vtk_to_numpy(a).reshape(a.GetNumberOfTuples(), -1)[:, 0]
    return np.ascontiguousarray(values, dtype=np.float64)


def build_stepper(
    mesh,
    a,
    clamps,
    fixed_values,
    lumped_mass,
    static,
    external_force=None,
    initial_displacement=None,
    initial_velocity=None,
    prescribed_mask=None,
    prescribed_u=None,
    speed_limit=_D["PrescribedSpeedLimit"],
):
    """A StepperDriver set up on `mesh` (the filter's BuildSolver): `a` the checked
    material (simulate_arguments), `clamps` simulate_clamps' plane and box, `fixed_values`
    one float per node or None. simulate() and the live loop (hoembed.live) use it."""
    plane = (
        () if clamps.get("plane") is None else tuple(clamps["plane"][0]) + tuple(clamps["plane"][1])
    )
    box = () if clamps.get("box") is None else tuple(clamps["box"])
    offsets, conn = _arrays.cells(mesh.GetCells())
    types = _arrays.cell_types(mesh)
    vectors = (external_force, initial_displacement, initial_velocity)
    driver = StepperDriver()
    try:
        driver.build(
            mesh.GetNumberOfPoints(),
            _arrays.points(mesh.GetPoints()),
            types,
            offsets,
            conn,
            [
                a["young"],
                a["poisson"],
                a["density"],
                a["dt"],
                a["rayleigh_mass"],
                a["rayleigh_stiffness"],
                a["solver_tolerance"],
            ],
            bool(lumped_mass),
            bool(static),
            list(a["gravity"]),
            list(plane),
            list(box),
            fixed_values,
            *(
                None if v is None else np.ascontiguousarray(v, dtype=np.float64).reshape(-1)
                for v in vectors
            ),
            prescribed_mask=None
            if prescribed_mask is None
            else np.ascontiguousarray(prescribed_mask, dtype=np.float64),
            prescribed_displacement=None
            if prescribed_u is None
            else np.ascontiguousarray(prescribed_u, dtype=np.float64).reshape(-1),
            prescribed_speed_limit=speed_limit,
            material_name=a.get("material"),
            hyperelastic=None
            if a.get("material") is None
            else [
                float(a["mooney_rivlin"][0]),
                float(a["mooney_rivlin"][1]),
                float(a["newton_tolerance"]),
                float(a["max_newton_iterations"]),
            ],
        )
    except RuntimeError as e:
        _fail(e)
    return driver


def simulate(
    fe_mesh,
    steps=_D["NumberOfTimeSteps"],
    dt=_D["TimeStep"],
    young=_D["YoungModulus"],
    poisson=_D["PoissonRatio"],
    density=_D["Density"],
    gravity=_D["Gravity"],
    fixed=None,
    rayleigh_mass=_D["RayleighMass"],
    rayleigh_stiffness=_D["RayleighStiffness"],
    external_force=None,
    initial_displacement=None,
    initial_velocity=None,
    lumped_mass=_D["LumpedMass"],
    static=_D["StaticSolve"],
    every=1,
    solver_tolerance=_D["SolverTolerance"],
    progress=None,
    prescribed=None,
    prescribed_speed_limit=_D["PrescribedSpeedLimit"],
    material=MATERIALS[_D["Material"]],
    mooney_rivlin=(_D["MooneyRivlinC10"], _D["MooneyRivlinC01"]),
    newton_tolerance=_D["NewtonTolerance"],
    max_newton_iterations=_D["MaxNewtonIterations"],
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
        progress,
    )
    # the law and Newton's controls: checked by the driver (its messages)
    a.update(
        material=str(material),
        mooney_rivlin=tuple(mooney_rivlin),
        newton_tolerance=newton_tolerance,
        max_newton_iterations=max_newton_iterations,
    )
    steps, dt, every = a["steps"], a["dt"], a["every"]
    mesh = pyvista.wrap(fe_mesh)
    prescribed_mask, prescribed_u, speed = simulate_prescribed(
        prescribed, prescribed_speed_limit, mesh.n_points
    )
    clamps = simulate_clamps(fixed, mesh.n_points)
    vectors = {}
    for key, value in (
        ("external_force", external_force),
        ("initial_displacement", initial_displacement),
        ("initial_velocity", initial_velocity),
    ):
        vectors[key] = None if value is None else simulate_vector(mesh.n_points, value, key)
    if mesh.GetNumberOfCells() == 0 or mesh.GetPoints() is None:
        _fail("The input mesh is empty (no cells).")
    if clamps["mask"] is not None:
        fixed_values = clamps["mask"].astype(np.float64)
    else:
        fixed_values = _fixed_values(mesh, clamps["name"] or N.Fixed)
    driver = build_stepper(
        mesh,
        a,
        clamps,
        fixed_values,
        lumped_mass,
        static,
        *vectors.values(),
        prescribed_mask=prescribed_mask,
        prescribed_u=prescribed_u,
        speed_limit=speed,
    )
    n, nc = mesh.n_points, mesh.n_cells
    # the input's structure, point and cell data (as the filter's CopyStructure and
    # PassData); no field data but the stepper's
    rest = mesh.copy()
    rest.field_data.clear()
    if clamps["mask"] is not None:
        rest.point_data[N.Fixed] = clamps["mask"]
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
        out.point_data[N.Displacement] = disp
        out.point_data[N.Velocity] = vel
        out.point_data[N.NodalRotation] = rot
        out.cell_data[N.VonMisesStress] = vm
        out.field_data[N.KineticEnergy] = np.array([kinetic])
        out.field_data[N.StrainEnergy] = np.array([strain])
        out.field_data[N.SolverIterations] = np.array([float(iterations)])
        out.field_data[N.TimeValue] = np.array([0.0 if static else k * dt])
        frames.append(out)
        if progress is not None:
            progress(i + 1, len(ks))
    return frames


simulate.__doc__ = SIMULATE_DOC
