"""Test designs shared by studies, benchmarks and tests (condition tables as column arrays)."""
from __future__ import annotations

import numpy as np


def cycles(n: int = 240, dt: float = 120.0) -> dict[str, np.ndarray]:
    """Seed 000 style: alternating -60 <-> 80 C from 20 C, ramps of 2 K/min and one-hour dwells,
    sampled every `dt` s (240 x 120 s = 8 h, a bit more than one cycle)."""
    t = np.arange(n) * dt
    leg = [(80.0, 30), (80.0, 60), (-60.0, 70), (-60.0, 60), (80.0, 70), (80.0, 60), (20.0, 30),
           (20.0, 30)]                                     # (set point C, minutes to reach / hold)
    kt, kT = [0.0], [20.0]
    while kt[-1] < t[-1]:
        for T, minutes in leg:
            kt.append(kt[-1] + 60.0 * minutes)
            kT.append(T)
    return {"time_s": t, "T_ambient_C": np.interp(t, kt, kT)}
