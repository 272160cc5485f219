"""Bearing stage: the pair equilibrium from the FE's groove-centre shifts
(`analytic.bearing.solve_pair` -> `PairState`), and what is read off the pair
(`PairSummary`: the pair's contact angle, the land margins, the static safety).

The position preload is set in each row's assembly state (T_ref, at rest: `fe_ref`); the
preload-path compliance per bearing (mm/N) is the assembly's (`[preload] path_compliance`) or a
run's override, with the inputs' `extra_compliance_mm_per_N` (the preload_path_compliance effect)
added in series (compliances of springs in series add). Units mm, N, MPa, deg, C.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.bearing import BearingGeometry, PairState, solve_pair
from analytic.bearing.state import take_rows
from analytic.bearing.land import land_diameters_mm, land_margin_deg
from analytic.safety import static_safety_from_contact_pressure
from studies.model.inputs import PhysicsInputs
from studies.model.stages.fe import FEState


@dataclass(frozen=True)
class PairSummary:
    """What is read off the pair per row, arrays (n,).

    contact_angle_deg: the pair's contact angle, the axial-force-weighted mean of bearings A and
    B (equal weights when both are unloaded), deg. land_margin_inner_deg, land_margin_outer_deg:
    the smaller over A and B of the angle between the contact ellipse's edge and the groove edge
    (`analytic.bearing.land.land_margin_deg`; < 0: the ellipse is truncated), deg.
    static_safety: s0 = (4200 MPa / p_max)^3 (ISO 76 through the contact pressure; inf for an
    unloaded pair), -."""
    contact_angle_deg: np.ndarray
    land_margin_inner_deg: np.ndarray
    land_margin_outer_deg: np.ndarray
    static_safety: np.ndarray


class BearingStage:
    """The pair of one assembly: geometry, the bearing span and the land diameters, built once."""

    def __init__(self, asm, bearing_span_mm: float, fe_compliance_mm_per_N=0.0):
        """asm: the `studies.model.config.Assembly`; bearing_span_mm: the distance of the ball
        planes (inner ring mid-planes) of bearings A and B, the lever of the rotor tilt under a
        moment or an off-centre radial load, mm."""
        self.asm = asm
        self.geom = BearingGeometry.from_spec(asm.bearing, asm.materials)
        #: inner and outer land diameters (mm): given, or from the effective ring section
        self.land_diameters_mm = land_diameters_mm(asm.bearing, asm.materials)[:2]
        self.bearing_span_mm = float(bearing_span_mm)
        #: the assembly's preload-path compliance per bearing (mm/N; 0: rigid; the pipeline sets
        #: the FE's value for `[preload] path_compliance = "fe"`)
        self.compliance_mm_per_N = fe_compliance_mm_per_N

    def arguments(self, inputs: PhysicsInputs, fe: FEState, fe_ref: FEState,
                  compliance_mm_per_N=None, ball_model: str | None = None) -> dict:
        """The keyword arguments of `analytic.bearing.solve_pair` for the rows (the pipeline
        memoises the equilibrium by them). compliance_mm_per_N: in place of the assembly's
        (scalar or per row); ball_model: "static" or "quasi_dynamic" in place of the
        assembly's `[operating] ball_model`."""
        a = self.asm
        ball_model = a.operating.ball_model if ball_model is None else ball_model
        preload = np.maximum(np.asarray(inputs.preload_assembled_N, float)
                             - np.asarray(inputs.preload_loss_N, float), 0.0)
        return dict(dr_mm=fe.dr_mm, dz_mm=fe.dz_mm, T_inner_ring_C=inputs.T_C["inner_ring"],
                    T_outer_ring_C=inputs.T_C["outer_ring"], T_ball_C=inputs.T_C["ball"],
                    T_ref_C=a.T_ref_C, preload_kind=a.preload.kind,
                    preload_assembled_N=preload, axial_load_N=inputs.axial_load_N,
                    radial_load_N=_zeros_if_none(inputs.radial_load_N),
                    moment_Nmm=_zeros_if_none(inputs.moment_Nmm),
                    bearing_span_mm=self.bearing_span_mm,
                    speed_rpm=np.asarray(inputs.speed_rpm, float), ball_model=ball_model,
                    control=a.operating.raceway_control,
                    dr_ref_mm=fe_ref.dr_mm, dz_ref_mm=fe_ref.dz_mm,
                    compliance_mm_per_N=(self.compliance_mm_per_N if compliance_mm_per_N is None
                                         else compliance_mm_per_N)
                    + inputs.extra_compliance_mm_per_N)

    def solve(self, arguments: dict) -> PairState:
        """The pair equilibrium (`analytic.bearing.solve_pair`) for `arguments`, each distinct
        row solved once (`distinct_rows`: a test programme repeats its steady points, a dwell
        repeats its row; the flywheel bench's speed and preload steps hold 130 distinct pair
        states in 500 rows), the same numbers bit for bit as solving every row."""
        n = _n_rows(arguments)
        rows = distinct_rows(arguments, n) if n > 2 else None     # (2,): bearings A, B
        if rows is None:
            return solve_pair(self.geom, self.asm.arrangement, **arguments)
        first, inverse = rows
        sub = {k: (np.asarray(v)[..., first] if _per_row(v, n) else v)
               for k, v in arguments.items()}
        return take_rows(solve_pair(self.geom, self.asm.arrangement, **sub), inverse)

    def summary(self, pair: PairState) -> PairSummary:
        """The `PairSummary` of a pair state."""
        margins = [land_margin_deg(self.geom, side, d_land, pair.contact_angle_deg, ell.a_mm).min(axis=0)
                   for side, d_land, ell in (("inner", self.land_diameters_mm[0], pair.inner),
                                             ("outer", self.land_diameters_mm[1], pair.outer))]
        with np.errstate(divide="ignore"):      # an unloaded pair has infinite static safety
            s0 = static_safety_from_contact_pressure(pair.max_contact_pressure_MPa)
        return PairSummary(weighted_contact_angle_deg(pair), *margins, s0)


def weighted_contact_angle_deg(pair: PairState) -> np.ndarray:
    """Contact angle of the pair (deg): the axial-force-weighted mean of bearings A and B (equal
    weights when both are unloaded). Continuous, unlike "the angle of the more loaded bearing",
    which jumps between two values when the forces are equal up to round-off."""
    FA, FB = pair.axial_force_N
    tot = FA + FB
    wA = np.where(tot > 0, FA / np.where(tot > 0, tot, 1.0), 0.5)
    return wA * pair.contact_angle_deg[0] + (1 - wA) * pair.contact_angle_deg[1]


def _zeros_if_none(v):
    return 0.0 if v is None else v


#: share of distinct rows above which the pair is solved on every row (the bookkeeping then
#: costs more than the rows it saves)
DISTINCT_SHARE_MAX = 0.8


def _per_row(v, n: int) -> bool:
    """True for an argument of `solve_pair` given per row ((n,) or (2, n)), not a scalar or a
    setting."""
    return isinstance(v, np.ndarray) and v.ndim >= 1 and v.shape[-1] == n and v.dtype.kind == "f"


def _n_rows(arguments: dict) -> int:
    """The number of rows of `solve_pair` arguments (1 when every argument is a scalar)."""
    return max((np.shape(v)[-1] for v in arguments.values()
                if isinstance(v, np.ndarray) and v.ndim >= 1), default=1)


def distinct_rows(arguments: dict, n: int) -> tuple[np.ndarray, np.ndarray] | None:
    """(first row of each distinct row, in row order; the distinct row of every row) of the
    per-row arguments of `solve_pair`, rows compared by their bit patterns (-0.0 and 0.0, and
    NaNs of other payloads, stay apart); None when more than DISTINCT_SHARE_MAX of the rows are
    distinct.

    Why the numbers do not change: every operation of the pair solvers is elementwise over the
    rows except the stopping rules of their iterations (`analytic.bearing.roots`: iterate until
    every row has converged; the outer loops: until the contact stiffness of every row matches),
    which take the largest over the rows. A repeated row runs the same iterations as its first
    occurrence, so leaving it out changes neither largest nor any row's iterates
    (tests/test_pipeline_rows.py holds the states equal bit for bit)."""
    cols = [np.asarray(v, float).reshape(-1, n) for v in arguments.values() if _per_row(v, n)]
    if not cols:
        return None
    keys = np.ascontiguousarray(np.vstack(cols).T).view(np.uint64)
    # a row hash first (a wrapping sum of the bit patterns times odd constants): rows with
    # distinct hashes are distinct, so more distinct hashes than DISTINCT_SHARE_MAX of the rows
    # decide without the exact comparison (np.unique over rows: 1 ms of 500, every pair solve)
    mix = np.random.default_rng(0).integers(1, 2**63, size=keys.shape[1], dtype=np.uint64) | 1
    if np.unique((keys * mix).sum(axis=1, dtype=np.uint64)).size > DISTINCT_SHARE_MAX * n:
        return None
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    if first.size > DISTINCT_SHARE_MAX * n:
        return None
    order = np.argsort(first, kind="stable")           # the distinct rows in row order
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    return first[order], rank[np.asarray(inverse).ravel()]

