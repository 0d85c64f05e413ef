"""Turn VTK error messages of a filter run into Python exceptions."""

from vtkmodules.vtkCommonCore import vtkCommand


class HOEmbedError(RuntimeError):
    """A HOEmbed filter (or a VTK filter it drives) reported an error."""


class _ErrorObserver:
    def __init__(self):
        self.errors = []
        self.warnings = []

    def __call__(self, obj, event, calldata=None):
        if calldata is None:
            calldata = ""
        if event == "ErrorEvent":
            self.errors.append(str(calldata).strip())
        else:
            self.warnings.append(str(calldata).strip())


def _attach_calldata(observer):
    # VTK passes the message as call data only when the callback says it wants a string.
    observer.CallDataType = "string0"
    return observer


def _clean(messages):
    """Keep the filters' own sentences: drop VTK's 'ERROR: In file, line N' headers and
    the executive's request dump when a filter said what went wrong."""
    own, executive = [], []
    for m in messages:
        lines = [ln for ln in m.splitlines() if ln.strip()]
        if lines and lines[0].startswith(("ERROR: In ", "Warning: In ")):
            lines = lines[1:]
        text = lines[0] if lines else m
        (executive if "returned failure for request" in text else own).append(text)
    return "\n".join(own or executive)


def _pipeline(algorithm):
    """``algorithm`` and every algorithm upstream of it (each once)."""
    seen, order, todo = set(), [], [algorithm]
    while todo:
        alg = todo.pop()
        key = alg.GetAddressAsString("vtkAlgorithm")
        if key in seen:
            continue
        seen.add(key)
        order.append(alg)
        for port in range(alg.GetNumberOfInputPorts()):
            for conn in range(alg.GetNumberOfInputConnections(port)):
                up = alg.GetInputAlgorithm(port, conn)
                if up is not None:
                    todo.append(up)
    return order


def run_filter(algorithm, warnings=None):
    """Update ``algorithm``; raise HOEmbedError with VTK's message if it, or an algorithm
    upstream of it, reports an error (or the pipeline update fails).

    Warnings are appended to the list ``warnings`` when one is given.
    """
    obs = _ErrorObserver()
    callback = _attach_calldata(lambda o, e, c=None: obs(o, e, c))
    attached = []
    for alg in _pipeline(algorithm):
        for target, events in (
            (alg, (vtkCommand.ErrorEvent, vtkCommand.WarningEvent)),
            (alg.GetExecutive(), (vtkCommand.ErrorEvent,)),
        ):
            for event in events:
                attached.append((target, target.AddObserver(event, callback)))
    try:
        # vtkAlgorithm.Update() returns None in Python (VTK 9.1); the executive's Update
        # returns 0 when this or an upstream request failed.
        port = 0 if algorithm.GetNumberOfOutputPorts() else -1
        ok = algorithm.GetExecutive().Update(port)
    finally:
        for target, i in attached:
            target.RemoveObserver(i)
    if warnings is not None:
        warnings.extend(obs.warnings)
    if obs.errors or not ok:
        raise HOEmbedError(_clean(obs.errors) or f"{algorithm.GetClassName()} failed")
    return algorithm.GetOutputDataObject(0)


# ---- argument checks of the pyvista-level functions ------------------------------------
# Types and shapes are checked here; a value's range is its driver's (check_range of the
# compiled module, hoembed::MesherRanges / StepperRanges), refused before any driver runs.


class HOEmbedArgumentError(HOEmbedError, ValueError):
    """A bad argument of a pyvista-level function, refused before any filter runs.

    A HOEmbedError (what every HOEmbed failure raises) and a ValueError (what Python
    code expects for a bad value)."""


def check_int(func, name, value, low=None, high=None):
    """``value`` as an int in [low, high]; bools, floats with a fraction, NaN refused."""
    import numbers

    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        if (
            isinstance(value, numbers.Real)
            and not isinstance(value, bool)
            and float(value).is_integer()
        ):
            value = int(value)
        else:
            raise HOEmbedArgumentError(f"{func}: {name} must be an integer, got {value!r}")
    value = int(value)
    if (low is not None and value < low) or (high is not None and value > high):
        raise HOEmbedArgumentError(f"{func}: {name} must be {_range_text(low, high)}, got {value}")
    return value


def check_real(
    func, name, value, low=None, high=None, low_open=False, high_open=False, finite=True
):
    """``value`` as a float in the range (bounds closed unless ``*_open``), finite unless
    ``finite`` is False (the caller then leaves the range to a driver's check_range)."""
    import math
    import numbers

    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        try:
            import numpy as np

            if isinstance(value, np.ndarray) and value.shape == ():
                value = value.item()
            else:
                raise TypeError
        except TypeError:
            raise HOEmbedArgumentError(f"{func}: {name} must be a number, got {value!r}") from None
    value = float(value)
    bad = finite and not math.isfinite(value)
    bad = bad or (low is not None and (value <= low if low_open else value < low))
    bad = bad or (high is not None and (value >= high if high_open else value > high))
    if bad:
        raise HOEmbedArgumentError(
            f"{func}: {name} must be a finite number{_range_text(low, high, low_open, high_open, ' ')}"
            f", got {value!r}"
        )
    return value


def check_vector(func, name, value, n=3):
    """``value`` as a tuple of ``n`` finite floats."""
    import numpy as np

    try:
        arr = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise HOEmbedArgumentError(f"{func}: {name} must be {n} numbers, got {value!r}") from None
    if arr.shape != (n,) or not np.all(np.isfinite(arr)):
        raise HOEmbedArgumentError(f"{func}: {name} must be {n} finite numbers, got {value!r}")
    return tuple(float(v) for v in arr)


def check_dataset(func, name, value, vtk_type):
    """``value`` must be a VTK dataset of class ``vtk_type`` (pyvista objects are)."""
    if not (hasattr(value, "IsA") and value.IsA(vtk_type)):
        kind = value.GetClassName() if hasattr(value, "GetClassName") else type(value).__name__
        raise HOEmbedArgumentError(
            f"{func}: {name} must be a {vtk_type} (or its pyvista wrapper), got {kind}"
        )
    return value


def check_callable(func, name, value):
    if value is not None and not callable(value):
        raise HOEmbedArgumentError(f"{func}: {name} must be callable or None, got {value!r}")
    return value


def _range_text(low, high, low_open=False, high_open=False, lead=""):
    if low is not None and high is not None:
        return f"{lead}in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
    if low is not None:
        return f"{lead}{'>' if low_open else '>='} {low:g}"
    if high is not None:
        return f"{lead}{'<' if high_open else '<='} {high:g}"
    return ""
