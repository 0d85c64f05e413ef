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
        for target, events in ((alg, (vtkCommand.ErrorEvent, vtkCommand.WarningEvent)),
                               (alg.GetExecutive(), (vtkCommand.ErrorEvent,))):
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
