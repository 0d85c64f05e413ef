"""The hoembed package: what it exposes, importing it first in a fresh interpreter, and
VTK errors turned into HOEmbedError (run_filter)."""

import os
import re
import subprocess
import sys
import textwrap

import hoembed
import pytest
import pyvista as pv
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
    from hoembed._hoembed import DEFAULTS

    assert (
        hoembed.vtkDeformationTransferFilter().GetFaceTolerance()
        == DEFAULTS["transfer"]["FaceTolerance"]
        == 1e-6
    )
    mesher = hoembed.vtkTet10Mesher()
    assert isinstance(mesher, vtkAlgorithm)
    assert mesher.GetClassName() == "vtkTet10Mesher"
    assert hasattr(mesher, "SetTargetNumberOfElements")


def _fresh_python(code):
    """Run ``code`` in a new interpreter (same environment, so the build tree's package
    is found); return the completed process."""
    return subprocess.run(
        [sys.executable, "-X", "faulthandler", "-c", textwrap.dedent(code)],
        capture_output=True,
        encoding="utf-8",
        timeout=120,
        env=dict(os.environ),
    )


@pytest.mark.parametrize(
    "first_import",
    [
        "import hoembed",
        "import hoembed.hoembedFiltersMeshing",
        "from hoembed import vtkTet10Mesher, tet10_mesh",
        "from hoembed.meshing import tet10_mesh",
    ],
)
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


# The filters' classes by the stage whose driver owns their defaults (the compiled module's
# DEFAULTS), and the functions' keywords by the property each sets.
FILTERS = {
    "mesher": "vtkTet10Mesher",
    "embedding": "vtkEmbeddingCoordinatesFilter",
    "transfer": "vtkDeformationTransferFilter",
    "stepper": "vtkCorotationalFEMStepper",
}
KEYWORDS = {
    "tet10_mesh": (
        "mesher",
        dict(
            n_elements="TargetNumberOfElements",
            edge_length="TargetEdgeLength",
            order="ElementOrder",
            curve_boundary="CurveBoundary",
            radius_edge_ratio="RadiusEdgeRatio",
            min_dihedral_angle="MinDihedralAngle",
            quality_target="CurvedQualityTarget",
            minimum_quality="MinimumQuality",
        ),
    ),
    "embed": ("embedding", dict(method="Method", n_partitions="NumberOfPartitions")),
    "transfer": (
        "transfer",
        dict(normals="NormalMode", compute_point_normals="ComputePointNormals"),
    ),
    "simulate": (
        "stepper",
        dict(
            steps="NumberOfTimeSteps",
            dt="TimeStep",
            young="YoungModulus",
            poisson="PoissonRatio",
            density="Density",
            gravity="Gravity",
            rayleigh_mass="RayleighMass",
            rayleigh_stiffness="RayleighStiffness",
            lumped_mass="LumpedMass",
            static="StaticSolve",
            solver_tolerance="SolverTolerance",
            prescribed_speed_limit="PrescribedSpeedLimit",
            material="Material",
            newton_tolerance="NewtonTolerance",
            max_newton_iterations="MaxNewtonIterations",
        ),
    ),
}
# the functions' names of the enumerated values (the filters' enumerations)
ENUM_VALUES = {
    "Method": {"normal-offset": 0, "barycentric": 1},
    "NormalMode": {"recompute": 0, "rotate": 1, "deform": 2},
    "Material": {"corotated": 0, "stvk": 1, "neo-hookean": 2, "mooney-rivlin": 3},
}


def _same(a, b):
    """Equal as the XML, the filters and Python spell them: bools as 0/1, vectors as
    tuples, a null string as ""."""

    def norm(v):
        if v is None:
            return ""
        if isinstance(v, (list, tuple)):
            return tuple(v)
        return int(v) if isinstance(v, bool) else v

    return norm(a) == norm(b)


def test_filters_take_the_drivers_defaults():
    """Each filter's properties start at its driver's defaults (the options structs the
    constructors copy), every property the driver has a default for."""
    from hoembed._hoembed import DEFAULTS

    assert set(DEFAULTS) == set(FILTERS)
    for stage, cls in FILTERS.items():
        alg = getattr(hoembed, cls)()
        assert DEFAULTS[stage], stage
        for name, value in DEFAULTS[stage].items():
            assert _same(getattr(alg, "Get" + name)(), value), (cls, name)


def test_functions_take_the_drivers_defaults():
    """The functions' keyword defaults are the drivers' (read from the compiled module,
    not written again), and their docstrings state those values."""
    import inspect

    from hoembed._hoembed import DEFAULTS

    for function, (stage, keywords) in KEYWORDS.items():
        params = inspect.signature(getattr(hoembed, function)).parameters
        for keyword, prop in keywords.items():
            default = params[keyword].default
            if prop in ENUM_VALUES:
                default = ENUM_VALUES[prop][default]
            assert _same(default, DEFAULTS[stage][prop]), (function, keyword)
    assert (
        f"(default {DEFAULTS['mesher']['TargetNumberOfElements']!r})" in hoembed.tet10_mesh.__doc__
    )
    assert f"(default {DEFAULTS['stepper']['Gravity']!r})" in hoembed.simulate.__doc__
    for doc in (hoembed.tet10_mesh.__doc__, hoembed.simulate.__doc__):
        assert not re.search(r"<[A-Z][A-Za-z]+>", doc)  # every <Name> replaced


def _xml_defaults():
    """(class, property, command, kind, values) of every ParaView XML property with a
    default_values attribute (information-only ones have none)."""
    import pathlib
    import xml.etree.ElementTree as ET

    xml = pathlib.Path(__file__).resolve().parents[2] / "Plugin" / "HOEmbed" / "HOEmbed.xml"
    out = []
    for proxy in ET.parse(xml).getroot().iter("SourceProxy"):
        for prop in proxy:
            if not prop.tag.endswith("VectorProperty") or "default_values" not in prop.attrib:
                continue
            kind = prop.tag[: -len("VectorProperty")]
            text = prop.attrib["default_values"]
            if kind == "String":
                values = text
            else:
                convert = int if kind == "Int" else float
                values = tuple(convert(v) for v in text.split())
                values = values[0] if len(values) == 1 else values
            out.append(
                (proxy.attrib["class"], prop.attrib["name"], prop.attrib["command"], kind, values)
            )
    return out


def test_paraview_xml_defaults_are_the_filters():
    """The plugin's XML has to write its default_values out: each must equal the filter's
    property right after construction (the driver's default), so that they cannot drift
    apart. The XML is parsed and compared with the VTK build's filters (ParaView's VTK
    compiles the same constructors)."""
    from hoembed._hoembed import DEFAULTS

    rows = _xml_defaults()
    classes = {row[0] for row in rows}
    assert classes == set(FILTERS.values())
    covered = set()
    for cls, name, command, kind, values in rows:
        assert command.startswith("Set"), (cls, name)
        alg = getattr(hoembed, cls)()
        prop = command[3:]
        got = getattr(alg, "Get" + prop)()
        # exact: the XML's decimal and the driver's literal are the same double
        assert _same(got, values), (cls, name, got, values)
        covered.add((cls, prop))
    # every XML default but VTK's own precision and the optional arrays' names (none by
    # default) is a driver's
    stage_of = {cls: stage for stage, cls in FILTERS.items()}
    assert {prop for cls, prop in covered if prop not in DEFAULTS[stage_of[cls]]} == {
        "OutputPointsPrecision",
        "ExternalForceArrayName",
        "InitialDisplacementArrayName",
        "InitialVelocityArrayName",
    }
    assert len(covered) == 47


def test_paraview_xml_ranges_are_the_drivers():
    """The XML's range domains are slider hints: each lies within its driver's valid range
    (hoembed::MesherRanges, StepperRanges, read from the compiled module's RANGES), an end
    the driver leaves open being the hint's end at most, so that the GUI never offers a
    value the driver refuses. Properties without a driver range are listed: a new one
    fails here until its driver states its range."""
    import pathlib
    import xml.etree.ElementTree as ET

    from hoembed._hoembed import RANGES

    xml = pathlib.Path(__file__).resolve().parents[2] / "Plugin" / "HOEmbed" / "HOEmbed.xml"
    stage_of = {cls: stage for stage, cls in FILTERS.items()}
    checked, without = set(), set()
    for proxy in ET.parse(xml).getroot().iter("SourceProxy"):
        stage = stage_of[proxy.attrib["class"]]
        for prop in proxy:
            for domain in prop:
                if domain.tag not in ("IntRangeDomain", "DoubleRangeDomain"):
                    continue
                name = prop.attrib["command"][3:]
                driver = RANGES.get(stage, {}).get(name)
                if driver is None:
                    without.add(name)
                    continue
                low, high, _, _, integer = driver
                assert integer == (domain.tag == "IntRangeDomain"), name
                hint_low, hint_high = domain.attrib.get("min"), domain.attrib.get("max")
                if low is not None:
                    assert hint_low is not None and float(hint_low) >= low, (name, hint_low, low)
                if high is not None:
                    assert hint_high is not None and float(hint_high) <= high, (
                        name,
                        hint_high,
                        high,
                    )
                checked.add(name)
    assert {
        "TargetNumberOfElements",
        "MinimumQuality",
        "RadiusEdgeRatio",
        "YoungModulus",
        "PoissonRatio",
        "Density",
        "TimeStep",
        "NumberOfTimeSteps",
    } <= checked
    assert "NumberOfPartitions" in checked and "FaceTolerance" in checked
    assert not without, without


def test_filters_refuse_what_their_driver_refuses():
    """No clamping set macro: a value outside the driver's range reaches the driver, whose
    sentence the filter reports (RequestData fails, nothing is changed silently)."""
    from hoembed._hoembed import check_range

    sphere = vtkSphereSource()
    sphere.Update()
    mesher = hoembed.vtkTet10Mesher()
    mesher.SetInputData(sphere.GetOutput())
    mesher.SetTargetNumberOfElements(0)
    assert mesher.GetTargetNumberOfElements() == 0
    sentence = check_range("mesher", "TargetNumberOfElements", 0)
    assert sentence.startswith("TargetNumberOfElements must be")
    with pytest.raises(hoembed.HOEmbedError, match=re.escape(sentence)):
        run_filter(mesher)
    assert check_range("mesher", "TargetNumberOfElements", 4) == ""
    # the stepper: a negative step count advertises no times and fails RequestData
    import numpy as np

    tet = pv.UnstructuredGrid(
        {pv.CellType.TETRA: np.array([[0, 1, 2, 3]])},
        np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]]),
    )
    stepper = hoembed.vtkCorotationalFEMStepper()
    stepper.SetInputData(tet)
    stepper.SetNumberOfTimeSteps(-1)
    sentence = check_range("stepper", "NumberOfTimeSteps", -1)
    with pytest.raises(hoembed.HOEmbedError, match=re.escape(sentence)):
        run_filter(stepper)
    with pytest.raises(ValueError, match="no range of Nope"):
        check_range("stepper", "Nope", 1.0)


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
