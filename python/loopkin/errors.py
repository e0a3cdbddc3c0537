"""The exceptions of loopkin: one class per kind of failure.

Every exception raised by the library is a :class:`KinematicsError`; each
kind also derives from the built-in exception a Python user would catch for
it (``ValueError`` for bad input, ``ArithmeticError`` for a pose that cannot
be solved). The message is the library's own: what went wrong and how to fix
it.
"""

from __future__ import annotations

from typing import List, Optional, Tuple

__all__ = [
    "KinematicsError",
    "DefinitionError",
    "NativeCodeError",
    "NotConvergedError",
    "SingularError",
    "NonFiniteError",
    "InvalidGeometryError",
    "WrongBranchError",
    "CannotAssembleError",
    "OutputError",
    "InvalidParameterError",
    "InvalidOptionError",
    "WrongLengthError",
    "InvalidDynamicsError",
    "RadiansWarning",
]


class KinematicsError(Exception):
    """Base class of every error of loopkin."""


class DefinitionError(KinematicsError, ValueError):
    """The text of a definition has errors.

    Attributes:
        diagnostics: every error, as (message, line, column, excerpt), line
            and column counted from 1 in the text given.
        line, column: where the first error is.
        excerpt: the text of that line.
        first: the first error's message.
    """

    diagnostics: List[Tuple[str, int, int, str]]
    line: int
    column: int
    excerpt: str
    first: str


class NativeCodeError(KinematicsError, RuntimeError):
    """No machine code can be generated for this host."""


class NotConvergedError(KinematicsError, ArithmeticError):
    """Newton–Raphson stopped above the tolerance: no pose near the guess
    closes the loops (past a limit position, or a poor guess)."""


class SingularError(KinematicsError, ArithmeticError):
    """The Jacobian of the loop equations with respect to the unknowns is
    singular at the pose (a dead-centre or toggle position)."""


class NonFiniteError(KinematicsError, ValueError):
    """An input (``name``) or a result is NaN or infinite."""

    name: Optional[str]
    value: Optional[float]


class InvalidGeometryError(KinematicsError, ValueError):
    """A geometric input is invalid (a point not of the mechanism, say)."""


class WrongBranchError(KinematicsError, ArithmeticError):
    """The pose found is on the other assembly branch than the one asked."""


class CannotAssembleError(KinematicsError, ArithmeticError):
    """A block solved in closed form has no real solution there: the links
    cannot close the loop (past a limit position)."""


class OutputError(KinematicsError, OSError):
    """A file could not be written."""


class InvalidParameterError(KinematicsError, ValueError):
    """A parameter (``name``) is invalid: not finite, a length not positive,
    or not a parameter of the mechanism."""

    name: Optional[str]
    value: Optional[float]


class InvalidOptionError(KinematicsError, ValueError):
    """An option is out of its range."""


class WrongLengthError(KinematicsError, ValueError):
    """An array has the wrong number of values."""


class InvalidDynamicsError(KinematicsError, ValueError):
    """The masses and loads cannot be used: the definition has no
    ``bodies`` or ``loads`` section, or a body, load or spring is invalid
    (a mass not positive, a value not finite)."""


class RadiansWarning(UserWarning):
    """An angle given as a plain number of more than two turns (4π), which
    is read in radians but was likely meant in degrees: ``phi=90`` is 14.3
    turns; write ``phi="90deg"``."""
