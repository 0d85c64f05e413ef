"""The hoembed package: what it exposes, importing it first in a fresh interpreter, and
VTK errors turned into HOEmbedError (run_filter)."""
import os
import subprocess
import sys
import textwrap

import pytest
import pyvista as pv

import hoembed
from hoembed._errors import run_filter
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm
from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter
from vtkmodules.vtkFiltersProgrammable import vtkProgrammableFilter
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader


def test_exports():
    assert isinstance(hoembed.__version__, str)
    assert issubclass(hoembed.HOEmbedError, RuntimeError)
    assert callable(hoembed.tet10_mesh)
    from hoembed._hoembed import TransferDriver
    assert (hoembed.vtkDeformationTransferFilter().GetFaceTolerance()
            == TransferDriver.DEFAULT_FACE_TOLERANCE == 1e-6)
    mesher = hoembed.vtkTet10Mesher()
    assert isinstance(mesher, vtkAlgorithm)
    assert mesher.GetClassName() == "vtkTet10Mesher"
    assert hasattr(mesher, "SetTargetNumberOfElements")


def _fresh_python(code):
    """Run ``code`` in a new interpreter (same environment, so the build tree's package
    is found); return the completed process."""
    return subprocess.run([sys.executable, "-X", "faulthandler", "-c", textwrap.dedent(code)],
                          capture_output=True, text=True, timeout=120, env=dict(os.environ))


@pytest.mark.parametrize("first_import", [
    "import hoembed",
    "import hoembed.hoembedFiltersMeshing",
    "from hoembed import vtkTet10Mesher, tet10_mesh",
    "from hoembed.meshing import tet10_mesh",
])
def test_import_first_in_fresh_interpreter(first_import):
    # VTK 9.1 segfaults when a wrapped module is imported before VTK's own modules: the
    # package must take care of that, whatever the user imports first.
    proc = _fresh_python(f"""
        import sys
        assert not any(m.startswith("vtkmodules") for m in sys.modules), "vtk preloaded"
        {first_import}
        import hoembed
        m = hoembed.vtkTet10Mesher()
        m.SetTargetNumberOfElements(123)
        print("OK", m.GetTargetNumberOfElements())
    """)
    assert proc.returncode == 0, f"rc={proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    assert "OK 123" in proc.stdout


def test_missing_file_raises_with_vtk_message():
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName("/nonexistent/hoembed/mesh.vtu")
    with pytest.raises(hoembed.HOEmbedError) as info:
        run_filter(reader)
    msg = str(info.value)
    assert "Error opening file" in msg and "/nonexistent/hoembed/mesh.vtu" in msg
    assert "vtkXMLUnstructuredGridReader" in msg
    assert "ERROR: In" not in msg and "returned failure for request" not in msg
    assert not reader.HasObserver("ErrorEvent")  # observers removed again


def test_upstream_failure_raises():
    # A filter whose input comes from a failing reader must not return an empty output
    # silently: the reader's message is raised.
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName("/nonexistent/hoembed/upstream.vtu")
    geometry = vtkGeometryFilter()
    geometry.SetInputConnection(reader.GetOutputPort())
    with pytest.raises(hoembed.HOEmbedError, match="Error opening file"):
        run_filter(geometry)
    assert not reader.HasObserver("ErrorEvent")
    assert not geometry.HasObserver("ErrorEvent")


def test_programmable_filter_error_and_warning():
    pf = vtkProgrammableFilter()
    pf.SetInputData(pv.Sphere())
    state = {"mode": "error"}

    def execute():
        pf.GetPolyDataOutput().ShallowCopy(pf.GetPolyDataInput())
        if state["mode"] == "error":
            pf.InvokeEvent("ErrorEvent", "the input has no cells worth meshing")
        else:
            pf.InvokeEvent("WarningEvent", "just a warning")

    pf.SetExecuteMethod(execute)
    with pytest.raises(hoembed.HOEmbedError, match="the input has no cells worth meshing"):
        run_filter(pf)
    state["mode"] = "warning"
    pf.Modified()
    warnings = []
    out = run_filter(pf, warnings=warnings)
    assert out.GetNumberOfCells() == pv.Sphere().n_cells
    assert warnings == ["just a warning"]


def test_success_returns_output():
    source = vtkSphereSource()
    geometry = vtkGeometryFilter()
    geometry.SetInputConnection(source.GetOutputPort())
    out = run_filter(geometry)
    assert out.GetNumberOfCells() > 0


def test_front_end_raises_on_bad_input():
    # An empty surface is refused by the mesher's driver, as HOEmbedError naming the
    # function; the wrapped filter names itself.
    with pytest.raises(hoembed.HOEmbedError) as info:
        hoembed.tet10_mesh(pv.PolyData())
    assert str(info.value).startswith("tet10_mesh: ")
    with pytest.raises(hoembed.HOEmbedError) as info:
        alg = hoembed.vtkTet10Mesher()
        alg.SetInputData(pv.PolyData())
        run_filter(alg)
    assert "vtkTet10Mesher" in str(info.value)


def test_defaults_are_the_drivers():
    """simulate()'s keyword defaults and vtkCorotationalFEMStepper's property defaults are
    the driver's (hoembed::StepperParameters); the mesher's services' defaults are
    vtkTet10Mesher's."""
    import inspect
    from hoembed._hoembed import MESHER_SERVICE_SETTINGS, StepperDriver
    defaults = StepperDriver.defaults()
    params = inspect.signature(hoembed.simulate).parameters
    for name, value in defaults.items():
        assert params[name].default == value, name
    stepper = hoembed.vtkCorotationalFEMStepper()
    for name, getter in (("young", "YoungModulus"), ("poisson", "PoissonRatio"),
                         ("density", "Density"), ("dt", "TimeStep"),
                         ("rayleigh_mass", "RayleighMass"),
                         ("rayleigh_stiffness", "RayleighStiffness"),
                         ("solver_tolerance", "SolverTolerance"),
                         ("lumped_mass", "LumpedMass"),
                         ("newton_tolerance", "NewtonTolerance"),
                         ("max_newton_iterations", "MaxNewtonIterations")):
        assert getattr(stepper, "Get" + getter)() == defaults[name], getter
    assert stepper.GetMaterialAsString() == defaults["material"]
    assert (stepper.GetMooneyRivlinC10(), stepper.GetMooneyRivlinC01()) == \
        defaults["mooney_rivlin"]
    mesher = hoembed.vtkTet10Mesher()
    assert mesher.GetMergeTolerance() == MESHER_SERVICE_SETTINGS["merge_tolerance"]
    assert (mesher.GetMaximumNumberOfElements()
            == MESHER_SERVICE_SETTINGS["maximum_number_of_elements"])


def test_one_source_tree():
    """The package's Python files are one tree: the build tree's copies are those of
    Wrapping/Python/hoembed, and no other package source is left (Wrapping/Pip has only
    the binding's C++ and its CMake project)."""
    import pathlib
    root = pathlib.Path(__file__).resolve().parents[2]
    source = root / "Wrapping" / "Python" / "hoembed"
    package = pathlib.Path(hoembed.__file__).parent
    for f in source.glob("*.py"):
        assert (package / f.name).read_bytes() == f.read_bytes(), f.name
    assert not list((root / "Wrapping" / "Pip").rglob("*.py"))
    assert hoembed.BACKEND == "vtk" and hasattr(hoembed, "vtkTet10Mesher")
    assert "_hoembed" in hoembed._hoembed.__name__
