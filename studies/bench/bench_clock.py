"""Wall and CPU seconds of a piece of work and the machine load beside it (benchmarks only).

CPU is user + system time of this process and of its children that have ended and were waited
for (resource.getrusage RUSAGE_SELF + RUSAGE_CHILDREN): the local Dask worker processes and a
gmsh child count once they have closed, so time a `with` block that closes its cluster. The load
is os.getloadavg() (1-minute) before and after: on a shared machine a load above the core count
means the wall time is inflated by other work, the CPU time much less so.
"""
from __future__ import annotations

import os
import resource
import time
from dataclasses import dataclass, field


def _cpu_s() -> float:
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime


@dataclass
class Clock:
    """`with Clock() as c: ...`; then c.wall_s, c.cpu_s, c.load_before, c.load_after."""
    wall_s: float = 0.0
    cpu_s: float = 0.0
    load_before: float = 0.0
    load_after: float = 0.0
    _t: tuple = field(default=(), repr=False)

    def __enter__(self) -> "Clock":
        self.load_before = os.getloadavg()[0]
        self._t = (time.perf_counter(), _cpu_s())
        return self

    def __exit__(self, *exc) -> bool:
        self.wall_s = time.perf_counter() - self._t[0]
        self.cpu_s = _cpu_s() - self._t[1]
        self.load_after = os.getloadavg()[0]
        return False

    def line(self) -> str:
        return (f"wall {self.wall_s:7.2f} s, CPU {self.cpu_s:7.2f} s, load {self.load_before:.2f}"
                f" -> {self.load_after:.2f} on {os.cpu_count()} cores")
