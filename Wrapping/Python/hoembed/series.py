"""Write time series (one .vtu / .vtp per step plus a .pvd collection)."""

import pyvista
from vtkmodules.vtkCommonCore import vtkCommand, vtkDoubleArray
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm

__all__ = ["write_series"]

from ._checks import WRITE_SERIES_DOC, series_frame_times, series_path
from ._errors import HOEmbedError, _ErrorObserver, _attach_calldata, _clean
from .hoembedIOSeries import vtkTimeSeriesWriter


def write_series(frames_or_algorithm, folder, name="series", times=None):
    path = series_path(folder, name)
    writer = vtkTimeSeriesWriter()
    writer.SetFileName(path)
    obs = _ErrorObserver()
    cb = _attach_calldata(lambda o, e, c=None: obs(o, e, c))
    writer.AddObserver(vtkCommand.ErrorEvent, cb)
    if isinstance(frames_or_algorithm, vtkAlgorithm):
        alg = frames_or_algorithm
        alg.GetExecutive().AddObserver(vtkCommand.ErrorEvent, cb)
        alg.AddObserver(vtkCommand.ErrorEvent, cb)
        if times is not None:
            arr = vtkDoubleArray()
            for t in times:
                arr.InsertNextValue(float(t))
            writer.SetTimeValues(arr)
        writer.SetInputConnection(alg.GetOutputPort())
        ok = writer.Write()
    else:
        frames = list(frames_or_algorithm)
        frame_times = series_frame_times(frames, times)
        ok = writer.BeginSeries()
        for frame, t in zip(frames, frame_times):
            if not ok:
                break
            data = frame if hasattr(frame, "GetClassName") else pyvista.wrap(frame)
            ok = writer.AddFrame(data, t)
        if ok:
            ok = writer.EndSeries()
    if not ok or obs.errors:
        raise HOEmbedError(_clean(obs.errors) or "vtkTimeSeriesWriter failed")
    return path


write_series.__doc__ = WRITE_SERIES_DOC
