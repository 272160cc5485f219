"""The typed result of one run of the model (`Pipeline.run`): one part per stage.

    result.fe / result.fe_ref   FE stage (`stages.fe.FEState`): the rows' FE answer and their
                                assembly states' (fit pressures, groove-centre shifts)
    result.fits                 the fit pressures by fit (`FitPressures`)
    result.lame                 the closed-form neighbours of the FE values (`LameNeighbours`),
                                computed when first read (`lame_of`; a diagnosis reads none)
    result.layer_names          the sleeve / cartridge layers (`Assembly.layers`, may be empty)
    result.pair                 bearing stage (`analytic.bearing.PairState`): preload, per-bearing
                                forces and contact angles, Hertz ellipses, stiffness, the radial
                                and quasi-dynamic states when present
    result.summary              read off the pair (`PairSummary`): pair contact angle, land
                                margins, static safety
    result.torque               torque stage (`analytic.friction.pair.TorqueComponents`)
    result.friction_coefficient the friction coefficient the torque used, per row
    result.checks               the assembly's checks per row (`studies.model.checks.Checks`)
    result.clamp                the preloaded clamps (`stages.fe.ClampState`; None unless a
                                `[nut]`/`[cover]` has clamp = "force")

Every array has one entry per row (axis -1 for the (2, n) per-bearing arrays of the pair and the
shifts, axis 0 otherwise). Units are in the field names (mm, N, MPa, deg, N*mm, W, C).
`studies.model.columns.to_columns` makes the named `simulate` columns of a result (the only place
they are made); code that builds on the model (a stiffness command, a transient FE, a report)
reads these typed fields.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property, partial
from typing import Callable

import numpy as np

from analytic.bearing import PairState
from analytic.friction.pair import TorqueComponents
from studies.model.checks import Checks
from studies.model.stages.bearing import PairSummary
from studies.model.stages.fe import ClampState, FEState
from studies.model.stages.lame import LameNeighbours


@dataclass(frozen=True)
class FitPressures:
    """Mean contact pressure of the fits, MPa. names: the FE fits (`fit_inner_A`, ...,
    `fit_sleeve`, `fit_cartridge`) in the column order of `per_fit_MPa` (n, n_fits);
    inner_MPa, outer_MPa (n,): the mean over the inner (shaft / inner rings) and over the outer
    (outer rings / housing or sleeve) fits."""
    names: tuple[str, ...]
    per_fit_MPa: np.ndarray
    inner_MPa: np.ndarray
    outer_MPa: np.ndarray

    @classmethod
    def of(cls, names, fe: FEState) -> "FitPressures":
        """The fit pressures of an FE state whose fits are `names`."""
        names = tuple(names)
        p = fe.fit_pressure_MPa
        p_in = p[:, [k for k, n in enumerate(names) if n.startswith("fit_inner")]]
        p_out = p[:, [k for k, n in enumerate(names) if n.startswith("fit_outer")]]
        return cls(names, p, p_in.mean(axis=1), p_out.mean(axis=1))

    def layer_MPa(self, layer: str) -> np.ndarray:
        """(n,) pressure of a sleeve's or cartridge's fit (`fit_<layer>`), MPa."""
        return self.per_fit_MPa[:, self.names.index(f"fit_{layer}")]


@dataclass(frozen=True)
class SimulationResult:
    """Everything one run of the model computes for n rows (see the module docstring).
    lame_of: computes the Lamé neighbours (`stages.lame.lame_neighbours` of this run), called
    once, when `lame` is first read."""
    fe: FEState
    fe_ref: FEState
    fits: FitPressures
    layer_names: tuple[str, ...]
    lame_of: Callable[[], LameNeighbours] = field(repr=False, compare=False)
    pair: PairState
    summary: PairSummary
    torque: TorqueComponents
    friction_coefficient: np.ndarray
    checks: Checks
    clamp: ClampState | None = None

    @cached_property
    def lame(self) -> LameNeighbours:
        """The closed-form neighbours of the FE values (`LameNeighbours`), computed on first
        read (`lame_of`) and kept."""
        return self.lame_of()

    def __getstate__(self) -> dict:
        """Pickled (a result sent back by a worker process): the Lamé neighbours computed and
        carried as values, not the FE stage that computes them."""
        return {**self.__dict__, "lame_of": partial(_given, self.lame)}

    @property
    def n_rows(self) -> int:
        return int(np.asarray(self.pair.preload_N).shape[0])

    # the headline outputs, for reading convenience (the same arrays as in the parts)
    @property
    def torque_Nmm(self) -> np.ndarray:
        """Friction torque of the pair, N*mm (`torque.torque_Nmm`)."""
        return self.torque.torque_Nmm

    @property
    def preload_N(self) -> np.ndarray:
        """Axial preload of the pair, N (`pair.preload_N`)."""
        return self.pair.preload_N

    @property
    def contact_angle_deg(self) -> np.ndarray:
        """The pair's contact angle, deg (`summary.contact_angle_deg`)."""
        return self.summary.contact_angle_deg

    @property
    def max_contact_pressure_MPa(self) -> np.ndarray:
        """Largest Hertz contact pressure of the pair, MPa (`pair.max_contact_pressure_MPa`)."""
        return self.pair.max_contact_pressure_MPa


def _given(value):
    """`value` itself (a pickled result's `lame_of`)."""
    return value
