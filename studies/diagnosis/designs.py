"""Test designs shared by studies, benchmarks and tests (condition tables as column arrays)."""
from __future__ import annotations

import numpy as np


def cycles(n: int = 240, dt: float = 120.0,
           speeds_rpm: tuple | None = None) -> dict[str, np.ndarray]:
    """Seed 000 style: alternating -60 <-> 80 C from 20 C, ramps of 2 K/min and one-hour dwells,
    sampled every `dt` s (240 x 120 s = 8 h, a bit more than one cycle). With `speeds_rpm`, a
    `speed_rpm` column holding each speed for an equal share of the rows in the order given
    (revolutions then accumulate at different rates in time; without it the assembly's configured
    speed applies)."""
    t = np.arange(n) * dt
    leg = [(80.0, 30), (80.0, 60), (-60.0, 70), (-60.0, 60), (80.0, 70), (80.0, 60), (20.0, 30),
           (20.0, 30)]                                     # (set point C, minutes to reach / hold)
    kt, kT = [0.0], [20.0]
    while kt[-1] < t[-1]:
        for T, minutes in leg:
            kt.append(kt[-1] + 60.0 * minutes)
            kT.append(T)
    out = {"time_s": t, "T_ambient_C": np.interp(t, kt, kT)}
    if speeds_rpm is not None:
        out["speed_rpm"] = np.asarray(speeds_rpm, float)[(np.arange(n) * len(speeds_rpm)) // n]
    return out


#: speeds of `speed_steps`, not in increasing order: a speed programme monotone in time makes an
#: effect growing with speed (a radial gradient) look like a sensor drift in time, which the
#: diagnosis then rightly refuses to name (`decision.versus_sensor_drift`); in this order the
#: speed staircase correlates 0.5 with time instead of 0.98
SPEEDS_RPM = (6000.0, 3000.0, 9000.0)


def speed_steps(n: int = 240, dt: float = 120.0,
                speeds_rpm: tuple = SPEEDS_RPM) -> dict[str, np.ndarray]:
    """Oil-lubricated spindle style: chamber steps 0, 20, 40, 60 C (the chamber follows its set
    point at 3 K/min) repeated at each speed (`SPEEDS_RPM`: 6000, 3000, 9000 rpm), sampled every
    `dt` s (240 x 120 s = 8 h)."""
    t = np.arange(n) * dt
    k = (np.arange(n) * 4 * len(speeds_rpm)) // n
    target = np.array([0.0, 20.0, 40.0, 60.0])[k % 4]
    amb = np.empty(n)
    amb[0] = target[0]
    for i in range(1, n):
        amb[i] = amb[i - 1] + np.clip(target[i] - amb[i - 1], -0.05 * dt, 0.05 * dt)
    return {"time_s": t, "T_ambient_C": amb, "speed_rpm": np.asarray(speeds_rpm, float)[k // 4]}
