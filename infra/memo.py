"""The one in-memory cache helper of bearingfem: `Memo`, a bounded, thread-safe map from a key to
a result, and `inputs_key`, a key of exact input bytes.

Rules, the same for every cache that uses it: at most `max_items` entries and at most `max_size`
in all (sizes as given to `put`, e.g. table rows); the entry used least recently goes first; a
single value larger than `max_size` is not kept. With `copy=True` a value is deep-copied on the way
in and out, so a caller that modifies what it got cannot change the cache (a result never depends
on whether it came from the cache); with `read_only=True` a value of arrays in frozen dataclasses
is kept as its `read_only` version and handed back, to the caller who put it too, without a copy
(a write into one of its arrays raises, numpy's "assignment destination is read-only"); plain
memos hand back the object itself (for values nobody modifies: FE states, factorisations,
pipelines). A lock makes `get`/`put`/`get_or_make` safe from
threads (the workers of a Dask cluster, `--scheduler`, run threads); `get_or_make` may build a missing value twice when two threads
ask at once, never a wrong one.

Users: `studies.model.pipeline` (pair equilibria by exact inputs) and, with its own rules,
`Pipeline.shared` (`Memo(max_items=4)`) and the FE state cache (`Memo(max_items=16)`) can be written
as `Memo`s; `fem.setup.shared_setup`-style process caches likewise.
"""
from __future__ import annotations

import copy as _copy
import dataclasses
import hashlib
import threading
from collections import OrderedDict
from typing import Callable, Hashable, TypeVar

import numpy as np

V = TypeVar("V")


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


def read_only(value):
    """`value` with each numpy array in it replaced by a read-only view of it (the data are not
    copied; the arrays themselves, which others may hold, stay writeable), through frozen
    dataclasses (rebuilt with `dataclasses.replace`) and tuples; anything else as it is."""
    if isinstance(value, np.ndarray):
        view = value.view()
        view.flags.writeable = False
        return view
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return dataclasses.replace(value, **{f.name: read_only(getattr(value, f.name))
                                             for f in dataclasses.fields(value) if f.init})
    if type(value) is tuple:
        return tuple(read_only(v) for v in value)
    return value


class Memo:
    """Up to `max_items` values (None: no limit) of total size up to `max_size` (None: no limit),
    least recently used dropped first; deep copies in and out with `copy`, values kept as their
    `read_only` version with `read_only` (module docstring). `hits`: values handed back from the
    cache."""

    def __init__(self, max_items: int | None = 16, max_size: float | None = None,
                 copy: bool = False, read_only: bool = False):
        if copy and read_only:
            raise ValueError("Memo: copy or read_only, not both")
        self.max_items, self.max_size, self.copy = max_items, max_size, bool(copy)
        self.read_only = bool(read_only)
        self._items: OrderedDict[Hashable, tuple[object, float]] = OrderedDict()
        self._size = 0.0
        self._lock = threading.Lock()
        self.hits = 0

    def __len__(self) -> int:
        return len(self._items)

    def __contains__(self, key: Hashable) -> bool:
        return key in self._items

    def get(self, key: Hashable, default=None):
        """The value kept for `key` (a deep copy with `copy`), or `default`."""
        with self._lock:
            hit = self._items.get(key)
            if hit is None:
                return default
            self._items.move_to_end(key)
            self.hits += 1
        return _copy.deepcopy(hit[0]) if self.copy else hit[0]

    def put(self, key: Hashable, value, size: float = 1.0):
        """Keep `value` (of `size`) for `key`, dropping the least recently used beyond the limits;
        a value larger than `max_size` on its own is not kept. Returns what a `get` of the key
        hands back (`value`, or its `read_only` version with `read_only`: give the caller this)."""
        if self.read_only:
            value = read_only(value)
        if self.max_size is not None and size > self.max_size:
            return value
        kept = _copy.deepcopy(value) if self.copy else value
        with self._lock:
            old = self._items.pop(key, None)
            if old is not None:
                self._size -= old[1]
            self._items[key] = (kept, float(size))
            self._size += float(size)
            while self._items and ((self.max_items is not None and len(self._items) > self.max_items)
                                   or (self.max_size is not None and self._size > self.max_size)):
                self._size -= self._items.popitem(last=False)[1][1]
        return value

    def get_or_make(self, key: Hashable, make: Callable[[], V], size: float = 1.0) -> V:
        """The value for `key`, made by `make()` and kept when missing."""
        missing = object()
        hit = self.get(key, missing)
        if hit is not missing:
            return hit
        value = self.put(key, make(), size)
        return _copy.deepcopy(value) if self.copy else value

    def clear(self) -> None:
        with self._lock:
            self._items.clear()
            self._size = 0.0
