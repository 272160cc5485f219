"""The pair-equilibrium memo of `studies.model.pipeline`: `infra.memo.Memo` with deep copies and a
row budget (the one in-memory cache helper; use it directly in new code).

A diagnosis evaluates the model many times at inputs that differ only in friction parameters
(the friction scale of the calibration, a solid-film run-in, a friction-temperature slope): the
bearing-pair equilibrium does not depend on them and is the same to the last bit. `Memo` keeps
the last few results by a hash of their inputs (`inputs_key`), so such a call reuses the
equilibrium instead of solving it again. The memo keeps the `read_only` version of a result
(`infra.memo.read_only`: its arrays read-only views) and hands that back, to the caller who put it
too, without copying: nobody can modify what the memo holds (a write raises), and a result
never depends on whether it came from the memo.
"""
from __future__ import annotations

from infra.memo import Memo as _Memo
from infra.memo import inputs_key

__all__ = ["Memo", "inputs_key"]


class Memo(_Memo):
    """The last `max_items` results (fewer when they hold more than `max_rows` rows in all; the
    least recently used go first) by `inputs_key`; `get` returns the kept value or None,
    `put(key, value, rows)` keeps the value's read-only version and returns it."""

    def __init__(self, max_items: int = 16, max_rows: int = 50_000):
        super().__init__(max_items=max_items, max_size=max_rows, read_only=True)
