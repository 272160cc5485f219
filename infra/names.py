"""The nearest valid name to a mistyped one, for error lines ("unknown key 'x' (did you mean
'y'?)"): `difflib.get_close_matches` (Ratcliff/Obershelp similarity, Python standard library)."""
from __future__ import annotations

import difflib

#: similarity (0..1, difflib's ratio) below which no name is offered
CUTOFF = 0.6


def did_you_mean(name: str, known) -> str:
    """` (did you mean 'NAME'?)` with the known name most like `name`, "" when none is alike."""
    hit = difflib.get_close_matches(name, [str(k) for k in known], n=1, cutoff=CUTOFF)
    return f" (did you mean '{hit[0]}'?)" if hit else ""
