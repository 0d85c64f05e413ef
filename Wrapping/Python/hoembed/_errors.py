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


def run_filter(algorithm, warnings=None):
    """Update ``algorithm``; raise HOEmbedError with VTK's message if it reports an error.

    Warnings are appended to the list ``warnings`` when one is given.
    """
    obs = _ErrorObserver()
    callback = _attach_calldata(lambda o, e, c=None: obs(o, e, c))
    ids = [algorithm.AddObserver(vtkCommand.ErrorEvent, callback),
           algorithm.AddObserver(vtkCommand.WarningEvent, callback)]
    executive = algorithm.GetExecutive()
    ids_exec = [executive.AddObserver(vtkCommand.ErrorEvent, callback)]
    try:
        ok = algorithm.Update()
    finally:
        for i in ids:
            algorithm.RemoveObserver(i)
        for i in ids_exec:
            executive.RemoveObserver(i)
    if warnings is not None:
        warnings.extend(obs.warnings)
    if obs.errors or ok == 0:
        raise HOEmbedError(_clean(obs.errors) or f"{algorithm.GetClassName()} failed")
    return algorithm.GetOutputDataObject(0)
