"""Write time series (one .vtu / .vtp per step plus a .pvd collection)."""

import os

import pyvista
from vtkmodules.vtkCommonCore import vtkCommand, vtkDoubleArray
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm

__all__ = ["write_series"]

from ._errors import HOEmbedError, _ErrorObserver, _attach_calldata, _clean
from .hoembedIOSeries import vtkTimeSeriesWriter


def _frame_time(frame, index):
    fd = getattr(frame, "field_data", None)
    if fd is not None and "TimeValue" in fd and len(fd["TimeValue"]):
        return float(fd["TimeValue"][0])
    return float(index)


def write_series(frames_or_algorithm, folder, name="series", times=None):
    """Write a time series readable by ParaView and ``pyvista.read``.

    Parameters
    ----------
    frames_or_algorithm : sequence of datasets, or a vtkAlgorithm
        Either frames (pyvista / VTK unstructured grids or poly data; each frame's time is
        its field data ``TimeValue`` when present, else its index, unless ``times`` is
        given), or a VTK algorithm whose output is written over its advertised time steps
        (or ``times``).
    folder : str or path
        Output folder (created if needed).
    name : str
        Series name: writes ``folder/name.pvd`` and ``folder/name/name_NNNNNN.vt[up]``.
    times : sequence of float, optional
        Times of the frames / times to request from the algorithm.

    Returns
    -------
    str
        Path of the .pvd file.

    Raises
    ------
    hoembed.HOEmbedError
        If a frame has an unsupported type or a non-finite time, the input fails, or the
        folder or a file cannot be written. Nothing is half-written: the frames go to a
        staging folder and replace an older series of the same name only once all of
        them and the .pvd are complete; on failure the older series is left intact.
    """
    folder = os.fspath(folder)
    name = str(name)
    if not name or name.startswith(".") or os.sep in name or (os.altsep and os.altsep in name):
        raise HOEmbedError(f"write_series: the series name {name!r} must be a plain file "
                           "name (no folder, not starting with '.')")
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as err:
        raise HOEmbedError(f"write_series: cannot create the output folder {folder!r}: "
                           f"{err.strerror or err}") from None
    if not os.access(folder, os.W_OK | os.X_OK):
        raise HOEmbedError(f"write_series: the output folder {folder!r} is not writable")
    path = os.path.join(folder, f"{name}.pvd")
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
        if times is not None and len(times) != len(frames):
            raise ValueError("times must have one value per frame")
        ok = writer.BeginSeries()
        for i, frame in enumerate(frames):
            if not ok:
                break
            data = frame if hasattr(frame, "GetClassName") else pyvista.wrap(frame)
            t = float(times[i]) if times is not None else _frame_time(frame, i)
            ok = writer.AddFrame(data, t)
        if ok:
            ok = writer.EndSeries()
    if not ok or obs.errors:
        raise HOEmbedError(_clean(obs.errors) or "vtkTimeSeriesWriter failed")
    return path
