"""The inverse question for a published rig: which stack within plausible bounds reproduces a
measured trend? A test instead of an inference.

The candidates are stacks of `design_search.candidates` (spacer materials and common length,
clamp scheme, effective ring sections) at the rig's assembled preload, each through the exact model (its own FE,
on the screening mesh); the target is a measured preload change at given temperatures. A stack
reproduces the trend when its preload change is within `tolerance_N` of the measurement at every
target temperature. The answer is the list of stacks that do, or the closest ones and how far
they miss.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from studies.model.parallel import map_blocks
from studies.usecases.design_search import SCREEN_MESH_FACTOR, Stack, evaluate_stack


@dataclass(frozen=True)
class TrendMatch:
    stack: Stack
    change_N: tuple[float, ...]        # preload change at the target temperatures (N)
    miss_N: float                      # largest |change - target| over the targets (N)


def match_trend(asm, stacks: list[Stack], T_target_C, change_target_N,
                mesh_factor: float = SCREEN_MESH_FACTOR, workers=None) -> list[TrendMatch]:
    """Every stack's preload change (T - T_ref) at the target temperatures, sorted by the
    largest miss."""
    T = np.unique(np.concatenate([np.asarray(T_target_C, float), [asm.T_ref_C]]))
    P0 = np.array([asm.preload.assembled_N])
    res = map_blocks(evaluate_stack, [(asm, s, T, P0, mesh_factor) for s in stacks],
                     workers=workers)
    i_ref = int(np.flatnonzero(T == asm.T_ref_C)[0])
    idx = [int(np.flatnonzero(T == t)[0]) for t in T_target_C]
    out = []
    for s, r in zip(stacks, res):
        P = r.preload_N[0]
        change = tuple(float(P[i] - P[i_ref]) for i in idx)
        miss = float(np.max(np.abs(np.array(change) - np.asarray(change_target_N, float))))
        out.append(TrendMatch(s, change, miss))
    return sorted(out, key=lambda m: m.miss_N)
