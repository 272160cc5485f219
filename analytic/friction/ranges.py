"""Where a friction law leaves its source's range: per law the quantity its source bounds and the
rows outside, reduced to one warning line per law and quantity for a whole run (`RangeNote`).

Ranges (each stated in its law's module): skf2004, n dm above `skf2004.NDM_LIMIT` (the
catalogue model ends at the bearing's limiting speed) and an oil level above
`skf2004.DRAG_LEVEL_MAX_DM` pitch diameters (the drag formula's range, the level taken there); ehl_rolling, the ellipticity k = a/b of a
loaded contact outside 1..8 (Hamrock-Dowson's fits, which the rolling force's groups follow);
starved, the supply ratio r = h_oil / h_ff below 0.01 (Chevalier et al. 1998's range, a film of
a few nm below it). Units: those of the quantity (mm/min, -).
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class RangeRows:
    """Rows of one evaluation where `law`'s `quantity` leaves `bound`: outside (n,) per row (any
    contact or ball of the row), lo and hi the quantity's extremes where outside (NaN if none)."""
    law: str
    quantity: str
    bound: str
    outside: np.ndarray
    lo: float
    hi: float


def range_rows(law: str, quantity: str, bound: str, value, outside) -> RangeRows:
    """`RangeRows` from the quantity's values and the outside mask, arrays (..., n): the rows
    are the last axis; any earlier axis (contacts, balls) is reduced with any()."""
    v = np.atleast_1d(np.asarray(value, float))
    o = np.broadcast_to(np.atleast_1d(np.asarray(outside, bool)), v.shape)
    rows = o.reshape(-1, o.shape[-1]).any(axis=0)
    lo, hi = (float(v[o].min()), float(v[o].max())) if o.any() else (np.nan, np.nan)
    return RangeRows(law, quantity, bound, rows, lo, hi)


def combine(*groups) -> tuple[RangeRows, ...]:
    """The `RangeRows` of several evaluations of the same rows (a pair's two bearings), one per
    law and quantity: rows outside in any, the extremes over all."""
    out: dict[tuple[str, str], RangeRows] = {}
    for r in (r for g in groups for r in g):
        k = (r.law, r.quantity)
        if k not in out:
            out[k] = r
            continue
        o = out[k]
        out[k] = replace(o, outside=o.outside | r.outside, lo=np.fmin(o.lo, r.lo),
                         hi=np.fmax(o.hi, r.hi))
    return tuple(out.values())


@dataclass(frozen=True)
class RangeNote:
    """A law's rows outside its source's range over a run: how many, the quantity's extremes."""
    law: str
    quantity: str
    bound: str
    rows: int
    lo: float
    hi: float

    def message(self, total_rows: int) -> str:
        """The one warning line."""
        return (f"friction law {self.law}: {self.quantity} outside its source's range "
                f"({self.bound}) in {self.rows} of {total_rows} rows ({self.lo:.3g} .. "
                f"{self.hi:.3g}): the law is extrapolated there")


def notes(ranges) -> tuple[RangeNote, ...]:
    """The `RangeNote` of each `RangeRows` with rows outside."""
    return tuple(RangeNote(r.law, r.quantity, r.bound, int(r.outside.sum()), r.lo, r.hi)
                 for r in ranges if r.outside.any())


def merge(a, b) -> tuple[RangeNote, ...]:
    """Two runs' notes (disjoint rows: chunks of one table) as one per law and quantity."""
    out: dict[tuple[str, str], RangeNote] = {}
    for n in (*a, *b):
        k = (n.law, n.quantity)
        o = out.get(k)
        out[k] = n if o is None else replace(o, rows=o.rows + n.rows, lo=min(o.lo, n.lo),
                                             hi=max(o.hi, n.hi))
    return tuple(out.values())
