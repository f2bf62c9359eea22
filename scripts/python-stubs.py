#!/usr/bin/env python3
"""Writes the type stubs of the Python module pushpred (python/pushpred/__init__.pyi) from the compiled module's own
signatures, which pybind11 writes as the first line of each docstring ("name(a: T, b: T = 1.0) -> R").

Usage: PYTHONPATH=build/python python3 scripts/python-stubs.py [--check] [OUT]
--check compares with OUT (default: python/pushpred/__init__.pyi) instead of writing it, and exits 1 when they
differ (tests/python/test_stubs.py runs it so). Debian 12 has no pybind11-stubgen; mypy's stubgen would need the
module's signatures in the same docstrings, so this reads them directly."""
import inspect
import re
import sys
from pathlib import Path

import pushpred
from pushpred import _core

HEADER = '''"""Type stubs of pushpred, written by scripts/python-stubs.py from the compiled module: do not edit."""
import os
from typing import Any, Callable, Dict, Iterable, List, Optional, Tuple

import numpy

'''


def clean(text):
    """A pybind11 type in stub form: the module's own classes by name, numpy arrays without their shape."""
    text = text.replace("pushpred._core.", "")
    return re.sub(r"numpy\.ndarray\[numpy\.\w+(\[[^\]]*\])?\]", "numpy.ndarray", text)


def split_parameters(inside):
    pieces, depth, start = [], 0, 0
    for k, c in enumerate(inside):
        if c in "[(":
            depth += 1
        elif c in "])":
            depth -= 1
        elif c == "," and depth == 0:
            pieces.append(inside[start:k].strip())
            start = k + 1
    if inside.strip():
        pieces.append(inside[start:].strip())
    return pieces


def signature_lines(name, doc, indent=""):
    """def lines for each signature of `name` in `doc` (several for an overloaded function)."""
    lines = []
    candidates = [line for line in (doc or "").splitlines() if re.match(rf"^(\d+\. )?{re.escape(name)}\(", line)]
    overloaded = len(candidates) > 1
    for line in candidates:
        line = re.sub(r"^\d+\. ", "", line)
        inside, _, result = line[len(name) + 1:].rpartition(") -> ")
        parameters = []
        for piece in split_parameters(inside):
            head, eq, _ = piece.partition(" = ")
            parameters.append(clean(head) + (" = ..." if eq else ""))
        if overloaded:
            lines.append(f"{indent}@overload")
        lines.append(f"{indent}def {name}({', '.join(parameters)}) -> {clean(result)}: ...")
    return lines


def class_lines(name, cls):
    bases = [b.__name__ for b in cls.__bases__ if b.__module__ in ("pushpred", "pushpred._core")]
    lines = [f"class {name}({', '.join(bases)}):" if bases else f"class {name}:"]
    body = []
    for attr, value in sorted(vars(cls).items()):
        if attr.startswith("_") and attr not in ("__init__", "__repr__", "__len__"):
            continue
        if isinstance(value, property):
            doc = (value.fget.__doc__ or "") if value.fget else ""
            match = re.match(r"^\(self: [^)]*\) -> (.*)$", doc.splitlines()[0] if doc else "")
            body.append(f"    @property\n    def {attr}(self) -> {clean(match.group(1)) if match else 'Any'}: ...")
        elif isinstance(value, staticmethod) or type(value).__name__ == "builtin_function_or_method":
            function = getattr(cls, attr)
            sig = signature_lines(attr, function.__doc__, "    ")
            body += ["    @staticmethod"] + sig if sig and not sig[0].strip().startswith("@") else sig
        elif type(value).__name__ == "instancemethod":
            body += signature_lines(attr, value.__doc__, "    ")
        elif inspect.isfunction(value):
            body.append(f"    def {attr}{inspect.signature(value)}: ...")
    return lines + (body or ["    ..."])


def stubs():
    out = [HEADER]
    out.append("__version__: str\n")
    out.append("class InputError(ValueError): ...\nclass SolverError(RuntimeError): ...\n")
    public = sorted(n for n in dir(pushpred) if not n.startswith("_") and n not in ("InputError", "SolverError"))
    for name in public:
        value = getattr(pushpred, name)
        if inspect.ismodule(value):
            continue
        if isinstance(value, type):
            out.append("\n".join(class_lines(name, value)) + "\n")
        elif hasattr(_core, name):
            out.append("\n".join(signature_lines(name, getattr(_core, name).__doc__)) + "\n")
        elif inspect.isfunction(value):
            out.append(f"def {name}{inspect.signature(value)}: ...\n")
    text = "\n".join(out)
    if "@overload" in text:
        text = text.replace("from typing import Any,", "from typing import Any, overload,", 1)
    return text


def main(argv):
    check = "--check" in argv
    paths = [a for a in argv if a != "--check"]
    path = Path(paths[0]) if paths else Path(__file__).resolve().parent.parent / "python/pushpred/__init__.pyi"
    text = stubs()
    if check:
        if not path.is_file() or path.read_text() != text:
            print(f"{path} is not the module's stubs: PYTHONPATH=build/python python3 scripts/python-stubs.py")
            return 1
        print(f"{path} matches the module")
        return 0
    path.write_text(text)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
