"""A small memo of model results by the exact bytes of their inputs.

A diagnosis evaluates the model many times at inputs that differ only in friction parameters
(the friction scale of the calibration, a solid-film run-in, a friction-temperature slope): the
bearing-pair equilibrium does not depend on them and is the same to the last bit. `Memo` keeps
the last few results by a hash of their inputs, so such a call reuses the equilibrium instead of
solving it again. A hit hands back a deep copy (callers may modify what they get), so a result
never depends on whether it came from the memo.
"""
from __future__ import annotations

import copy
import hashlib

import numpy as np


def inputs_key(values: dict) -> bytes:
    """SHA-1 of named inputs: each name, and each value's dtype, shape and bytes (numbers and
    arrays; None and strings by their text). Equal keys mean bitwise equal inputs."""
    h = hashlib.sha1()
    for name in sorted(values):
        v = values[name]
        h.update(name.encode() + b"\0")
        if v is None or isinstance(v, str):
            h.update(b"s" + str(v).encode() + b"\0")
            continue
        a = np.ascontiguousarray(np.asarray(v))
        h.update(f"{a.dtype.str}{a.shape}".encode() + b"\0")
        h.update(a.tobytes())
    return h.digest()


class Memo:
    """The last `max_items` results (fewer when they hold more than `max_rows` rows in all; the
    oldest go first) by `inputs_key`. `get` returns a deep copy or None."""

    def __init__(self, max_items: int = 16, max_rows: int = 50_000):
        self.max_items, self.max_rows = int(max_items), int(max_rows)
        self._items: dict[bytes, tuple[object, int]] = {}
        self.hits = 0

    def get(self, key: bytes):
        hit = self._items.get(key)
        if hit is None:
            return None
        self.hits += 1
        return copy.deepcopy(hit[0])

    def put(self, key: bytes, value, rows: int) -> None:
        """Keep `value` (a deep copy) for `key`; a result of more than `max_rows` rows is not kept."""
        if rows > self.max_rows:
            return
        self._items.pop(key, None)
        self._items[key] = (copy.deepcopy(value), int(rows))
        while (len(self._items) > self.max_items
               or sum(r for _, r in self._items.values()) > self.max_rows):
            self._items.pop(next(iter(self._items)))
