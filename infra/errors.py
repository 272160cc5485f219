"""The package's own error and warning categories, defined here (the first layer) so that every
layer may raise or emit them and `bearingfem` re-exports them (`bearingfem.BearingfemError`,
`bearingfem.BearingfemWarning`) without any layer importing the facade.

- `BearingfemError` (a ValueError): input the model cannot work with, bad or unworkable (a
  malformed table, a fit the contact solver cannot settle). Its message is the one line the
  command prints before exiting with code 2.
- `BearingfemWarning` (a UserWarning): input that is legal but implausible (Fahrenheit in a
  Celsius column, a contact angle in radians, a viscosity law used far outside its fit) and the
  summaries of violated limits. Its text is the line the command prints after
  `bearingfem COMMAND: warning: `.
"""
from __future__ import annotations

import warnings
from typing import Iterable


class BearingfemError(ValueError):
    """Bad or unworkable input: one line naming the file, field or row and the problem."""


class BearingfemWarning(UserWarning):
    """Legal but implausible input, or a violated limit: one line, the run goes on."""


def emit(lines: Iterable[str], stacklevel: int = 3) -> None:
    """Each line as a `BearingfemWarning` (Python's warning filters decide what is shown; by
    default each distinct line once per calling location). stacklevel 3: the caller of the
    function that calls `emit` (a notebook cell calling `bearingfem.simulate`)."""
    for line in lines:
        warnings.warn(line, BearingfemWarning, stacklevel=stacklevel)
