"""pyvista-level write_series().

The series' files (staging folder, refusals, the .pvd, the atomic swap-in, cleanup) are
hoembed::SeriesFiles, the class vtkTimeSeriesWriter runs, through _hoembed; each frame is
written here by the XML writers of the VTK Python in use, with vtkTimeSeriesWriter's
settings (appended data, zlib), into the staged path SeriesFiles gives. The errors are the
writer's sentences, after "write_series: ".
"""

import pyvista
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkUnstructuredGrid
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm, vtkStreamingDemandDrivenPipeline
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter, vtkXMLUnstructuredGridWriter

from ._checks import WRITE_SERIES_DOC, series_frame_times, series_path
from ._errors import HOEmbedError, _attach_calldata, _clean, _ErrorObserver
from ._hoembed import SeriesFiles

__all__ = ["write_series"]

_SDDP = vtkStreamingDemandDrivenPipeline


def _watch(obs, *objects):
    """Collect the ErrorEvents of `objects` into obs (VTK then prints nothing)."""
    cb = _attach_calldata(lambda o, e, c=None: obs(o, e, c))
    return [(o, o.AddObserver(vtkCommand.ErrorEvent, cb)) for o in objects]


def _unwatch(attached):
    for o, i in attached:
        o.RemoveObserver(i)


def _check(call, *args):
    """A SeriesFiles call; its error sentence as HOEmbedError (it abandoned the series)."""
    try:
        return call(*args)
    except RuntimeError as e:
        raise HOEmbedError(f"write_series: {e}") from None


def _add_frame(files, data, time):
    # the type decides the writer (vtkTimeSeriesWriter::AddFrame); SeriesFiles refuses
    # the rest with its message
    if isinstance(data, vtkUnstructuredGrid):
        ext, writer, copy = "vtu", vtkXMLUnstructuredGridWriter(), vtkUnstructuredGrid()
    elif isinstance(data, vtkPolyData):
        ext, writer, copy = "vtp", vtkXMLPolyDataWriter(), vtkPolyData()
    else:
        ext = writer = copy = None
    type_name = data.GetClassName() if data is not None else ""
    staged = _check(files.start_frame, time, ext or "", type_name)
    # a shallow copy, as the VTK writer: the writer's pipeline does not take over the
    # caller's data object
    copy.ShallowCopy(data)
    writer.SetInputData(copy)
    writer.SetFileName(staged)
    writer.SetDataModeToAppended()
    writer.SetCompressorTypeToZLib()
    obs = _ErrorObserver()
    attached = _watch(obs, writer)
    try:
        written = writer.Write() == 1 and writer.GetErrorCode() == 0 and not obs.errors
    finally:
        _unwatch(attached)
    _check(files.finish_frame, written)


def _algorithm_series(files, path, alg, times):
    """What vtkTimeSeriesWriter::Write does, through the user's pip VTK: the algorithm's
    output at each of SeriesFiles.input_times (its TIME_STEPS, or `times`), updated
    through its executive with UPDATE_TIME_STEP."""
    obs = _ErrorObserver()
    exe = alg.GetExecutive()
    attached = _watch(obs, alg, exe)

    def fail(sentence):
        # as the VTK build reports it: the input's own errors and this sentence, the
        # executive's request dump left out when there are such
        files.abandon()
        raise HOEmbedError(_clean(obs.errors + [f"write_series: {sentence}"]))

    try:
        if alg.GetNumberOfOutputPorts() < 1 or not isinstance(exe, _SDDP):
            fail("The input's executive does not support time requests.")
        if not exe.UpdateInformation():
            fail("The input failed to provide its information.")
        info = alg.GetOutputInformation(0)
        advertised = (
            [float(t) for t in (info.Get(_SDDP.TIME_STEPS()) or ())]
            if info.Has(_SDDP.TIME_STEPS())
            else None
        )
        steps, timed = SeriesFiles.input_times(
            None if times is None else [float(t) for t in times], advertised
        )
        _check(files.begin, path)
        for k, t in enumerate(steps):
            if timed:
                info.Set(_SDDP.UPDATE_TIME_STEP(), t)
            if not exe.Update(0) or obs.errors:
                fail(SeriesFiles.input_failed(t, k))
            _add_frame(files, alg.GetOutputDataObject(0), t)
    finally:
        _unwatch(attached)


def write_series(frames_or_algorithm, folder, name="series", times=None):
    path = series_path(folder, name)
    files = SeriesFiles()
    try:
        if isinstance(frames_or_algorithm, vtkAlgorithm):
            _algorithm_series(files, path, frames_or_algorithm, times)
        else:
            frames = list(frames_or_algorithm)
            frame_times = series_frame_times(frames, times)
            _check(files.begin, path)
            for frame, t in zip(frames, frame_times):
                data = frame if hasattr(frame, "GetClassName") else pyvista.wrap(frame)
                _add_frame(files, data, t)
        _check(files.end)
    finally:
        # whatever failed (here or in the user's VTK), nothing half-written stays
        if files.is_open:
            files.abandon()
    return path


write_series.__doc__ = WRITE_SERIES_DOC
