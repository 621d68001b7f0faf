"""Errors and warnings: one class per diagnostic-code family.

Every error the library raises is an :class:`AuditError` carrying the
diagnostic's ``code`` (the stable kebab-case name the CLI prints, e.g.
``parse``), the ``file``, ``line`` and ``column`` where known, the
``message`` (what was expected and what was found) and an optional
``help``. Warnings (suspicious but usable input) go through Python's
:mod:`warnings` module as :class:`AuditWarning` subclasses with the same
attributes, so ``warnings.simplefilter("error", ConventionWarning)`` makes a
unit mistake fatal and ``warnings.catch_warnings(record=True)`` collects
them.
"""

from __future__ import annotations

import warnings
from typing import Optional, Sequence, Tuple, Type


class _Diagnostic:
    """The attributes shared by errors and warnings."""

    code: str
    file: Optional[str]
    line: Optional[int]
    column: Optional[int]
    message: str
    help: Optional[str]

    def _set(self, code, file, line, column, message, help_):
        self.code = code
        self.file = file
        self.line = line
        self.column = column
        self.message = message
        self.help = help_

    def location(self) -> str:
        """``file:line:column`` with the parts that are known."""
        if self.file is None:
            return "<input>" if self.line is not None else ""
        parts = [self.file]
        if self.line is not None:
            parts.append(str(self.line))
            if self.column is not None:
                parts.append(str(self.column))
        return ":".join(parts)

    def _text(self, severity: str) -> str:
        where = self.location()
        head = f"{severity}[{self.code}]: " + (f"{where}: " if where else "")
        tail = f"\n  help: {self.help}" if self.help else ""
        return head + self.message + tail


class AuditError(_Diagnostic, Exception):
    """An input or usage error (the CLI's exit code 2)."""

    def __init__(self, message, code="usage", file=None, line=None, column=None, help=None):
        self._set(code, file, line, column, message, help)
        super().__init__(self._text("error"))


class InputError(AuditError):
    """A file that cannot be used: unreadable (``io``), malformed
    (``parse``), numbers that are no rigid transform (``invalid``), or
    beyond a resource limit (``limit``)."""


class FrameError(AuditError, LookupError):
    """A frame-graph problem (``frames``): an unknown frame, frames not
    connected, a cycle, two parents, a joint that must be set."""


class UsageError(AuditError, ValueError):
    """Arguments that ask for something impossible (``usage``), or
    warnings refused (``warnings-denied``)."""


class AuditWarning(_Diagnostic, UserWarning):
    """Suspicious input: the answer is still given."""

    def __init__(self, message, code="ignored", file=None, line=None, column=None, help=None):
        self._set(code, file, line, column, message, help)
        super().__init__(self._text("warning"))


class ConventionWarning(AuditWarning):
    """A unit or convention the numbers may not be in: millimetres in a metre
    field, degrees in a radian field, an assumed convention, a URDF 1.0
    ``quat_xyzw`` that ROS ignores."""


class NumericWarning(AuditWarning):
    """Numbers repaired as they were read: a rotation off orthonormal, a
    quaternion or joint axis off unit length."""


class JointWarning(AuditWarning):
    """A movable joint taken at its default position, or outside its limits."""


class GraphWarning(AuditWarning):
    """How the files fit together: a duplicate or disagreeing redundant edge,
    an ambiguous key, a frame name that resembles another or is padded, a
    URDF that ROS refuses, a value ignored."""


_ERRORS = {
    "io": InputError,
    "parse": InputError,
    "invalid": InputError,
    "limit": InputError,
    "frames": FrameError,
    "usage": UsageError,
    "warnings-denied": UsageError,
}

_WARNINGS = {
    "millimetres-in-metre-field": ConventionWarning,
    "degrees-in-radian-field": ConventionWarning,
    "assumed-convention": ConventionWarning,
    "quat-xyzw-ignored": ConventionWarning,
    "non-orthonormal-rotation": NumericWarning,
    "non-unit-quaternion": NumericWarning,
    "non-unit-axis": NumericWarning,
    "joint-at-default": JointWarning,
    "joint-outside-limit": JointWarning,
}

DiagTuple = Tuple[str, str, Optional[str], Optional[int], Optional[int], str, Optional[str]]


def error_class(code: str) -> Type[AuditError]:
    """The exception class of a diagnostic code (a code added later: the base)."""
    return _ERRORS.get(code, AuditError)


def warning_class(code: str) -> Type[AuditWarning]:
    """The warning class of a diagnostic code (any other code: GraphWarning)."""
    return _WARNINGS.get(code, GraphWarning)


def make_error(code, severity, file, line, column, message, help_):
    """The exception for a diagnostic tuple (called by the native module)."""
    del severity  # always "error" here
    return error_class(code)(message, code, file, line, column, help_)


def warn_all(diags: Sequence[DiagTuple], stacklevel: int = 3) -> None:
    """Each diagnostic through :func:`warnings.warn`, in its code's class."""
    for code, _severity, file, line, column, message, help_ in diags:
        cls = warning_class(code)
        warnings.warn(cls(message, code, file, line, column, help_), stacklevel=stacklevel)
