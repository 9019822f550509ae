"""Errors that name a problem in the user's input and what to do about it.

Every exception raised for bad input derives from :class:`MasslineError`; the
command line turns it into a one-line message and exit code 2.

A message names the caller's parameters with :func:`param`, never with a command-line flag:

    raise MasslineError(f"{param('band', f'({lo:g}, {hi:g})', cli=f'{lo:g} {hi:g}')}: give LO < HI")

``str(err)`` spells each parameter as the library calls it (``band=(3, 5): …``); a caller with names of its own
renders the same error with :meth:`MasslineError.spelled` and its table of names: the command line's
(``massline/cli/options.py`` ``FLAGS``, ``band`` → ``--band``) gives ``--band 3 5: …``.
"""

from __future__ import annotations

import re
import sys
from collections.abc import Mapping

_START, _SEPARATOR, _END = "\x02", "\x01", "\x03"  # control characters no message or user input holds
_MARKED = re.compile(f"{_START}([^{_SEPARATOR}]*){_SEPARATOR}([^{_SEPARATOR}]*){_SEPARATOR}([^{_END}]*){_END}")


def param(name: str, value: str = "", *, cli: str | None = None) -> str:
    """A parameter named in an error message, with the value the message shows (if any).

    Parameters
    ----------
    name : str
        The library's name of the parameter: an argument (``"band"``, ``"sensor_mass"``) or a field of one
        (``"budget.triaxial"``, ``"options.sensor_base"``).
    value : str
        The value as a library caller writes it (``"(lo, hi)"``, ``"'abc'"``): shown as ``name=value``.
    cli : str, optional
        The value as the command line writes it after its flag (``"LO HI"``); ``value`` when not given.

    Returns
    -------
    str
        A marker to put in the message; :class:`MasslineError` renders it.
    """
    shown = value if cli is None else cli
    return f"{_START}{name}{_SEPARATOR}{value}{_SEPARATOR}{shown}{_END}"


class MasslineError(ValueError):
    """Bad input: the message names the problem and the remedy; parameters in it are marked by :func:`param`."""

    @property
    def message(self) -> str:
        """The message as raised, parameters still marked."""
        return str(self.args[0]) if self.args else ""

    @property
    def parameters(self) -> tuple[str, ...]:
        """The names of the parameters the message names, in its order."""
        return tuple(match.group(1) for match in _MARKED.finditer(self.message))

    def spelled(self, names: Mapping[str, str]) -> str:
        """The message with each parameter in ``names`` spelled as there (e.g. ``"--band"``, its value after a
        space); the others as the library calls them (``name`` or ``name=value``)."""

        def spell(match: re.Match) -> str:
            name, value, shown = match.groups()
            if name in names:
                return f"{names[name]} {shown}" if shown else names[name]
            return f"{name}={value}" if value else name

        return _MARKED.sub(spell, self.message)

    def __str__(self) -> str:
        return self.spelled({})


class SingularLayoutError(MasslineError):
    """A sensor/exciter layout whose equations are singular, with the reason."""


def solver_errors() -> tuple[type[Exception], ...]:
    """cvxpy's SolverError where cvxpy is loaded, else nothing: for an ``except`` clause around a step that may
    solve a convex problem, so that importing the module costs nothing (cvxpy takes ~0.9 s to load, and a
    SolverError can only be raised once it is loaded)."""
    module = sys.modules.get("cvxpy.error")
    return (module.SolverError,) if module is not None else ()
