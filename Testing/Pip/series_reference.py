"""write_series references of the VTK build (vtkTimeSeriesWriter) for test_pip_series.py.

generate_reference.py calls write(outdir) after its cases: with the VTK build's
hoembed.write_series it writes, under outdir/series/, series of frames that the
references already hold as files (the stepper's frames of each case as .vtu, its
transferred surfaces as .vtp), a series of a temporal VTK algorithm (TimedSphere, below:
the same class runs in both builds), and the error messages of bad calls (errors.json).
The wheel's test reads the same frame files, writes them with the wheel's write_series
and compares.
"""

import json
import os

import numpy as np

# the series written from reference files: (series name, case-relative frame file
# names, times: None = the frames' TimeValue field data, else explicit)
STEPPER_SERIES = ("stepper", "stepper_plane_{}.vtu", None)
SURFACE_SERIES = ("surface", "transferred_recompute_{}.vtp", [0.0, 0.25])


def frame_files(info, series):
    """The reference files of `series` for a case described by cases.json's `info`."""
    _, pattern, _ = series
    count = info["stepper"]["plane"]["frames"] if series is STEPPER_SERIES else info["frames"]
    return [pattern.format(i) for i in range(count)]


def timed_sphere_class():
    """A VTK source with TIME_STEPS (0, 0.5, 1.5): a sphere whose radius is 1 + t, a
    point array 'Height' = z * t, field data TimeValue. Made on call, so that importing
    this module needs no VTK."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as SDDP
    from vtkmodules.vtkFiltersSources import vtkSphereSource

    class TimedSphere(VTKPythonAlgorithmBase):
        TIMES = (0.0, 0.5, 1.5)

        def __init__(self):
            VTKPythonAlgorithmBase.__init__(
                self, nInputPorts=0, nOutputPorts=1, outputType="vtkPolyData"
            )

        def RequestInformation(self, request, inInfo, outInfo):
            info = outInfo.GetInformationObject(0)
            info.Set(SDDP.TIME_STEPS(), self.TIMES, len(self.TIMES))
            info.Set(SDDP.TIME_RANGE(), [self.TIMES[0], self.TIMES[-1]], 2)
            return 1

        def RequestData(self, request, inInfo, outInfo):
            info = outInfo.GetInformationObject(0)
            t = info.Get(SDDP.UPDATE_TIME_STEP()) if info.Has(SDDP.UPDATE_TIME_STEP()) else 0.0
            src = vtkSphereSource()
            src.SetRadius(1.0 + t)
            src.SetThetaResolution(12)
            src.SetPhiResolution(8)
            src.Update()
            out = vtkPolyData.GetData(outInfo)
            out.ShallowCopy(src.GetOutput())
            z = vtk_to_numpy(out.GetPoints().GetData())[:, 2]
            h = numpy_to_vtk(np.ascontiguousarray(z * t, dtype=np.float64), deep=True)
            h.SetName("Height")
            out.GetPointData().AddArray(h)
            tv = numpy_to_vtk(np.array([t], dtype=np.float64), deep=True)
            tv.SetName("TimeValue")
            out.GetFieldData().AddArray(tv)
            return 1

    return TimedSphere


def failing_sphere():
    """A TimedSphere that fails (RequestData returns 0) past t = 1."""
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as SDDP

    class FailingSphere(timed_sphere_class()):
        def RequestData(self, request, inInfo, outInfo):
            if outInfo.GetInformationObject(0).Get(SDDP.UPDATE_TIME_STEP()) > 1.0:
                return 0
            return super().RequestData(request, inInfo, outInfo)

    return FailingSphere()


def bad_calls(pv, write_series, folder):
    """The bad calls whose messages both builds must give: name -> (callable, folder)."""

    def frames(k):
        out = []
        for i in range(k):
            f = pv.Sphere(radius=1.0 + i)
            f.field_data["TimeValue"] = np.array([float(i)])
            out.append(f)
        return out

    def pvd_is_folder():
        os.makedirs(os.path.join(folder, "d.pvd"), exist_ok=True)
        write_series(frames(1), folder, "d")

    def foreign_file():
        os.makedirs(os.path.join(folder, "mine"), exist_ok=True)
        with open(os.path.join(folder, "mine", "notes.txt"), "w") as f:
            f.write("keep me")
        write_series(frames(1), folder, "mine")

    return {
        "unsupported_type": lambda: write_series(
            frames(2) + [pv.ImageData(dimensions=(2, 2, 2))], folder, "s"
        ),
        "nan_time": lambda: write_series(frames(2), folder, "s", times=[0.0, float("nan")]),
        "inf_time": lambda: write_series(frames(2), folder, "s", times=[float("-inf"), 1.0]),
        "pvd_is_folder": pvd_is_folder,
        "foreign_file": foreign_file,
        "bad_name": lambda: write_series(frames(1), folder, "../up"),
        "dot_name": lambda: write_series(frames(1), folder, ".hidden"),
        "no_frames": lambda: write_series([], folder, "empty"),
        "failing_algorithm": lambda: write_series(failing_sphere(), folder, "alg"),
    }


def sentence(message):
    """The writer's sentence of an error message, without who said it (the VTK build:
    'vtkTimeSeriesWriter (0x...): ', the wheel: 'write_series: ')."""
    message = message.strip()
    if message.startswith("vtkTimeSeriesWriter (") and "): " in message:
        return message.split("): ", 1)[1]
    if message.startswith("write_series: "):
        return message[len("write_series: ") :]
    return message


def write(outdir):
    import hoembed
    import pyvista as pv

    outdir = os.path.abspath(outdir)  # the messages hold the paths: the test replaces them
    cases = json.load(open(os.path.join(outdir, "cases.json")))
    root = os.path.join(outdir, "series")
    for case, info in cases.items():
        for series in (STEPPER_SERIES, SURFACE_SERIES):
            name, _, times = series
            frames = [pv.read(os.path.join(outdir, case, f)) for f in frame_files(info, series)]
            hoembed.write_series(
                frames,
                os.path.join(root, case),
                name,
                times=times[: len(frames)] if times else None,
            )
    hoembed.write_series(timed_sphere_class()(), os.path.join(root, "algorithm"), "sphere")
    errors = {}
    for key in bad_calls(pv, None, None):
        folder = os.path.join(root, "bad", key)
        os.makedirs(folder, exist_ok=True)
        try:
            bad_calls(pv, hoembed.write_series, folder)[key]()
        except hoembed.HOEmbedError as e:
            errors[key] = str(e)
        else:
            raise SystemExit(f"series_reference: {key} did not fail in the VTK build")
    with open(os.path.join(root, "errors.json"), "w") as f:
        json.dump(errors, f, indent=1)
    print(f"[reference] series: {len(cases)} cases, {len(errors)} error messages")
