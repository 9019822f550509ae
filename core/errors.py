"""Errors that name a problem in the user's input and what to do about it.

Every exception raised for bad input derives from :class:`MasslineError`; the
command line turns it into a one-line message and exit code 2.
"""


class MasslineError(ValueError):
    """Bad input: the message names the problem and the remedy."""


class SingularLayoutError(MasslineError):
    """A sensor/exciter layout whose equations are singular, with the reason."""
