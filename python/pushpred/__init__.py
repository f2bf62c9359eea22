"""pushpred: predict where an object pushed by a robot will go, and explain why predictions miss.

Python bindings of the pushpred C++ library (J. Kim, "Position prediction using disturbance observer for planar
pushing"). Read a push with load_push(); run the disturbance observer (estimate_disturbance, QFilterObserver) and
the PID reconstruction (PidForceReconstruction); fit the relation d_hat = beta u + eps (RecursiveLeastSquares,
BatchLeastSquaresFit); run the paper's prediction study (run_prediction_study); simulate pushes (simulate); and
diagnose what the model lacks (diagnose, EffectLibrary).

Units and frames, everywhere: SI inside (metres, radians, newtons, newton metres, seconds), in the reference
frame {R} of the recordings; names carry their unit (t_s, force_N, ...). Poses are n x 3 arrays (x [m], y [m],
yaw [rad]); channels of forces are (x [N], y [N], torque about the object centre [N m]). Prediction errors are
reported in millimetres and degrees, as the library reports them. Results are numpy arrays and plain dicts;
errors are InputError (a ValueError) or SolverError (a RuntimeError) with the library's message. Long calls
release the GIL.
"""
import sys as _sys

try:
    from ._core import *  # noqa: F401,F403
    from ._core import __version__, InputError, SolverError, load_push  # noqa: F401
except ImportError as _error:
    # A module built for one interpreter fails in another with a bare "initialization failed" (or an undefined
    # symbol): say which interpreter it was built for.
    from . import _build

    raise ImportError(
        f"pushpred was built for {_build.python_executable} (Python {_build.python_version}, with numpy); this is "
        f"{_sys.executable} (Python {_sys.version.split()[0]}): run it with that interpreter, or build pushpred "
        f"for this one (pip install --no-build-isolation . with it, or cmake -DPython3_EXECUTABLE={_sys.executable}; "
        f"docs/python.md). The import failed with: {_error}") from _error

def _signature_from_doc(function):
    """inspect.Signature of a compiled function, from the first line of its docstring, which pybind11 writes as
    "name(a: T, b: T = default) -> R" (None for an overloaded one). Defaults that are not Python literals keep their
    text as their repr."""
    import ast
    import inspect

    first = (function.__doc__ or "").split("\n", 1)[0]
    name = function.__name__
    if not first.startswith(name + "(") or ") -> " not in first:
        return None
    inside = first[len(name) + 1:first.rindex(") -> ")]
    parameters, depth, start = [], 0, 0
    pieces = []
    for k, c in enumerate(inside):  # split at the commas outside brackets
        depth += c in "[(" and 1 or (c in "])" and -1 or 0)
        if c == "," and depth == 0:
            pieces.append(inside[start:k])
            start = k + 1
    if inside.strip():
        pieces.append(inside[start:])

    class _Default:
        def __init__(self, text):
            self.text = text

        def __repr__(self):
            return self.text

    for piece in pieces:
        piece = piece.strip()
        if piece.startswith("**"):
            parameters.append(inspect.Parameter(piece[2:].split(":")[0], inspect.Parameter.VAR_KEYWORD))
            continue
        head, _, default_text = piece.partition(" = ")
        pname = head.split(":")[0].strip()
        default = inspect.Parameter.empty
        if default_text:
            try:
                default = ast.literal_eval(default_text)
            except (ValueError, SyntaxError):
                default = _Default(default_text)
        kind = inspect.Parameter.POSITIONAL_OR_KEYWORD
        if any(p.kind == inspect.Parameter.VAR_KEYWORD for p in parameters):
            kind = inspect.Parameter.KEYWORD_ONLY
        parameters.append(inspect.Parameter(pname, kind, default=default))
    return inspect.Signature(parameters)


def _with_signatures(namespace):
    """Gives every compiled module-level function of `namespace` a Python wrapper whose inspect.signature() is the
    compiled one's (pybind11 functions have none: inspect.signature raises ValueError on them)."""
    import functools

    for name, function in list(namespace.items()):
        if name.startswith("_") or type(function).__name__ != "builtin_function_or_method":
            continue
        signature = _signature_from_doc(function)
        if signature is None:
            continue

        def make(compiled):
            @functools.wraps(compiled)
            def wrapper(*args, **kwargs):
                return compiled(*args, **kwargs)
            return wrapper

        wrapper = make(function)
        wrapper.__signature__ = signature
        wrapper.__module__ = "pushpred"
        namespace[name] = wrapper


_with_signatures(globals())


class ForceLawEffect:
    """Base for a candidate effect written in Python, registered with EffectLibrary.register().

    A force law adds to the object's generalized force a term linear in its parameters theta:
    f(state) = sum_j theta_j * unit_force(j, setting, state, shape). The diagnosis fits theta on the residual
    the paper's method leaves, keeps the effect when it explains enough of it, and adds it to the prediction.
    Override kind(), description(), parameters() and unit_force(); the rest is optional.
    """

    def kind(self):
        """Short identifier, unique within a library."""
        raise NotImplementedError

    def description(self):
        """One line: the physical term."""
        return self.kind()

    def parameters(self):
        """[(name, unit), ...], one pair per parameter."""
        raise NotImplementedError

    def unit_force(self, parameter, setting, state, shape):
        """[f_x [N], f_y [N], torque [N m]] per unit of parameter `parameter`.

        state: dict of 3-vectors pose (x [m], y [m], theta [rad]), velocity (m/s, m/s, rad/s), input (the
        applied force [N, N] and torque about the centre [N m]) and start_pose; shape: dict with mass_kg,
        inertia_kgm2 and the outline's dimensions [m]."""
        raise NotImplementedError

    def needs_friction_base(self):
        """True: tested only against a friction law (as the library's friction refinements are)."""
        return False


def run_batch(paths, job, progress=True):
    """Calls job(path) for every path; a failing path does not stop the batch.

    Returns (results, failures): results as a list of (path, job's result), failures as a list of
    (path, reason), the reason being the library's message without the path it starts with. progress: True prints
    one line per file to stderr ("[3/90] name: ok"), a callable is called as progress(index, total, path,
    reason_or_None), False is silent."""
    paths = [str(p) for p in paths]
    results, failures = [], []
    for i, path in enumerate(paths, start=1):
        error = None
        try:
            results.append((path, job(path)))
        except (InputError, SolverError) as e:
            error = str(e)
            if error.startswith(path + ": "):
                error = error[len(path) + 2:]
            failures.append((path, error))
        if callable(progress):
            progress(i, len(paths), path, error)
        elif progress:
            name = path.rsplit("/", 1)[-1]
            print(f"[{i}/{len(paths)}] {name}: {'ok' if error is None else 'failed: ' + error}",
                  file=_sys.stderr, flush=True)
    return results, failures


def recordings(folder=None, surface=""):
    """The recordings below `folder` (default: data_folder()) and `surface` (e.g. "abs"), sorted by name."""
    return list_recordings(data_folder(folder), surface)  # noqa: F405


__all__ = [name for name in dir() if not name.startswith("_")]
