"""Published measurements as data (issue 23 item 7): one model extension at a time, its one
parameter fitted on ONE published number, the other published number held out and predicted.

Seed 001 (flywheel hybrid pair, 7 N position preload, MAC oil): torque(-20 C)/torque(20 C) =
1.333..1.50 and torque(60 C)/torque(20 C) = 0.75 (the paper's conclusion 2). Each candidate's
parameter is fitted on the cold ratio alone (to the geometric centre of the published band, within
the parameter's physical bounds); the hot ratio is then its prediction. Candidates: the listed
effects (`studies.model.effects`, their own bounds and sources) and the switches of the assembly
file the configuration does not use (a starved film: a lower Palmgren f0; the bearing's own
temperature above the chamber's; a spring preload; quasi-dynamic balls; another oil of the
project's library).

Seed 000 (MoS2 pair, 100 N position preload): after repeated -60 <-> 80 C cycles the torque maximum
of a cycle is 1.7 N mm lower and its minimum 0.9 N mm higher than in the first cycle. The history
candidates the brief names (`solid_film_runin`, `preload_settling`, `preload_settling.creep`) are
fitted on one of the two numbers and predict the other.

Every model number comes through `studies.model.pipeline.simulate_table` (the one route) with the
effects by name; nothing here computes torque itself. Units: N, mm, C, K, s.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from analytic.lubrication import lubricant_library
from studies.diagnosis.designs import cycles as cycle_design
from studies.model.config import Assembly, load_shipped
from studies.model.effects import get_effect
from studies.model.pipeline import Pipeline, simulate_table

#: seed 001, the paper's conclusion 2: +33.3..50.0 % at -20 C, -25 % at 60 C (against 20 C)
SEED001_COLD_BAND = (1.333, 1.500)
SEED001_HOT = 0.75
SEED001_T_C = (-20.0, 20.0, 60.0)
#: the tolerance a held-out hot ratio is judged with: the relative half-width of the published
#: cold band, (1.5 - 1.333) / (1.5 + 1.333) = 5.9 %, the only statement of the rig's scatter the
#: paper gives (the hot point is one rounded number, "25 %")
SEED001_REL_TOL = (SEED001_COLD_BAND[1] - SEED001_COLD_BAND[0]) / sum(SEED001_COLD_BAND)
#: seed 000 (Fig. 11 and conclusion 3): steady cycle minus first cycle, torque max and min, N mm
SEED000_MAX_CHANGE_NMM = -1.7
SEED000_MIN_CHANGE_NMM = 0.9
#: half the last printed digit of the published 1.7 / 0.9 N mm
SEED000_TOL_NMM = 0.05
#: seed 000's cycle (`studies.diagnosis.designs.cycles`: 20 C start, -60 <-> 80 C at 2 K/min with
#: one-hour dwells, 410 min per cycle), five cycles sampled every 5 min: the first and the last
SEED000_CYCLE_MIN = 410.0
SEED000_CYCLES = 5
SEED000_DT_S = 300.0

#: bearing temperature above the chamber, K: upper bound (assumption, stated in the report): the
#: MAC oil kept below about 120 C at the 60 C chamber point (the Pennzane family's usual upper
#: operating temperature; not a datum of this project's lubricant table)
SELF_HEATING_MAX_K = 60.0


@dataclass(frozen=True)
class Candidate:
    """One model extension with at most one free parameter (empty `parameter`: a model form with
    nothing to fit, both published numbers are then predictions)."""
    name: str
    parameter: str
    bounds: tuple[float, float]
    bound_source: str
    #: value -> (assembly, extra condition columns per base row, effects)
    setup: Callable[[float], tuple[Assembly, dict, dict | None]]
    #: seed 000: the extension acts from the second cycle on (the first cycle is the baseline)
    after_first_cycle: bool = False


@dataclass(frozen=True)
class HeldOutFit:
    """A candidate fitted on one published number and its prediction of the other."""
    candidate: str
    parameter: str
    bounds: tuple[float, float]
    bound_source: str
    value: float                 # fitted value (NaN: nothing to fit)
    reaches: bool                # the target is reached inside the bounds (else: closest value)
    fitted: float                # the model's value of the fitted number at `value`
    fit_in_band: bool            # ... inside the published band (or tolerance)
    predicted: float             # the held-out number predicted
    predicted_ok: bool           # ... within the published value's tolerance


@dataclass(frozen=True)
class PublishedAsData:
    """All candidates against one published pair of numbers."""
    fitted_name: str
    fitted_target: float
    fitted_band: tuple[float, float]
    held_out_name: str
    held_out_published: float
    held_out_tol: float          # absolute tolerance of the held-out comparison
    configured: tuple[float, float]   # the configured model's (fitted, held-out) numbers
    fits: tuple[HeldOutFit, ...]

    @property
    def best(self) -> HeldOutFit:
        """The candidate whose fitted number comes closest to its band (log distance)."""
        lo, hi = self.fitted_band
        return min(self.fits, key=lambda f: _band_distance(f.fitted, lo, hi))

    @property
    def any_fits(self) -> bool:
        return any(f.fit_in_band for f in self.fits)


def _band_distance(v: float, lo: float, hi: float) -> float:
    """Distance of v from the band [lo, hi], relative (0 inside), sign-safe for changes."""
    if lo <= v <= hi:
        return 0.0
    scale = max(abs(lo), abs(hi), 1e-300)
    return min(abs(v - lo), abs(v - hi)) / scale


def _grid(lo: float, hi: float, n: int) -> np.ndarray:
    """Linear and (on each side of zero) logarithmic points over [lo, hi]: responses that
    saturate (a compliance, a clipped friction coefficient) change within a small part of the
    range."""
    pts = [np.linspace(lo, hi, n)]
    if hi > 0:
        pts.append(np.geomspace(max(lo, 1e-4 * hi) if lo > 0 else 1e-4 * hi, hi, n))
    if lo < 0:
        pts.append(-np.geomspace(max(-hi, 1e-4 * -lo) if hi < 0 else 1e-4 * -lo, -lo, n))
    g = np.unique(np.concatenate(pts))
    return g[(g >= lo) & (g <= hi)]


def _fit_one(cand: Candidate, quantity: Callable[[Candidate, float], tuple[float, float]],
             target: float, band: tuple[float, float], published: float, tol: float,
             n_grid: int = 9) -> HeldOutFit:
    """Fit the candidate's parameter so that the first number of `quantity` meets `target`:
    brentq on the first grid interval that brackets it; if none does, the grid value closest to
    it, refined by a bounded scalar minimisation of the miss between its neighbours. Then
    predict the second number."""
    if not cand.parameter:
        q, h = quantity(cand, np.nan)
        return HeldOutFit(cand.name, "", cand.bounds, cand.bound_source, float("nan"), False,
                          float(q), bool(band[0] <= q <= band[1]), float(h),
                          bool(abs(h - published) <= tol))
    lo, hi = cand.bounds
    grid = _grid(lo, hi, n_grid)
    vals = np.array([quantity(cand, x)[0] for x in grid])
    r = vals - target
    idx = np.flatnonzero(r[:-1] * r[1:] <= 0)
    if idx.size:
        i = int(idx[0])
        v = (grid[i] if r[i] == 0 else grid[i + 1] if r[i + 1] == 0 else
             brentq(lambda x: quantity(cand, x)[0] - target, grid[i], grid[i + 1],
                    rtol=1e-9, xtol=1e-12 * max(abs(lo), abs(hi))))
    else:
        i = int(np.argmin(np.abs(r)))
        a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        res = minimize_scalar(lambda x: abs(quantity(cand, x)[0] - target), bounds=(a, b),
                              method="bounded", options={"xatol": 1e-6 * (hi - lo)})
        v = res.x if abs(res.fun) < abs(r[i]) else grid[i]
    q, h = quantity(cand, float(v))
    return HeldOutFit(cand.name, cand.parameter, cand.bounds, cand.bound_source, float(v),
                      bool(idx.size), float(q), bool(band[0] <= q <= band[1]), float(h),
                      bool(abs(h - published) <= tol))


# --------------------------------------------------------------------------------- seed 001
def _effect_bounds(name: str, parameter: str) -> tuple[float, float]:
    return tuple(float(b) for b in get_effect(name).bounds[parameter])


def seed001_candidates(asm: Assembly) -> list[Candidate]:
    """The single-parameter extensions and the parameter-free model forms tried on seed 001."""
    lub = asm.lubrication
    cands = []
    for eff, par, src in (
            ("viscosity_temperature", "slope_factor",
             "effect bounds: ASTM D341 slopes of space oils (effects/viscosity_temperature.py)"),
            ("friction_temperature", "dmu_per_K",
             "effect bounds: MoS2/boundary friction data (effects/friction_temperature.py)"),
            ("preload_path_compliance", "extra_compliance_um_per_kN",
             "effect bounds: 0 to a wave-spring preload, VDI 2230 (effects/preload_path_compliance.py)")):
        cands.append(Candidate(eff, par, _effect_bounds(eff, par), src,
                               lambda v, e=eff, p=par: (asm, {}, {e: {p: v}})))
    cands.append(Candidate(
        "starved film (Palmgren f0)", "viscous_factor_f0", (0.0, float(lub.viscous_factor_f0)),
        "0: no viscous drag; the paper's oil-bath value 1.7 (Palmgren; Harris & Kotzalas Vol. 2 "
        "ch. 2 f0 table) as the upper bound: an oil-impregnated cage feeds less, not more",
        lambda v: (replace(asm, lubrication=replace(lub, viscous_factor_f0=v)), {}, None)))
    cands.append(Candidate(
        "bearing above the chamber (rings and balls)", "dT_K", (0.0, SELF_HEATING_MAX_K),
        f"0: no self-heating; {SELF_HEATING_MAX_K:g} K: assumption, the MAC oil below about 120 C "
        "at the 60 C point (the oil's usual upper operating temperature)",
        lambda v: (asm, {"dT_K": v}, None)))
    cands.append(Candidate("spring preload (same 7 N)", "", (np.nan, np.nan), "no parameter",
                           lambda v: (replace(asm, preload=replace(asm.preload, kind="spring")),
                                      {}, None)))
    cands.append(Candidate("quasi-dynamic balls", "", (np.nan, np.nan), "no parameter",
                           lambda v: (replace(asm, operating=replace(asm.operating,
                                                                     ball_model="quasi_dynamic")),
                                      {}, None)))
    for name in lubricant_library():
        if name == lub.lubricant:
            continue
        try:
            lubricant_library()[name].walther()
        except ValueError:          # fewer than two viscosity points in the project data
            continue
        cands.append(Candidate(f"oil: {name}", "", (np.nan, np.nan), "the project's oil table",
                               lambda v, n=name: (replace(asm, lubrication=replace(lub, lubricant=n)),
                                                  {}, None)))
    return cands


def seed001_torques(asm: Assembly, columns: dict | None = None, effects: dict | None = None,
                    dT_K: float = 0.0, mesh_factor: float = 1.0) -> dict[str, np.ndarray]:
    """The model at the three published temperatures (chamber = `T_ambient_C`; the rings and
    balls `dT_K` above it when given): `simulate_table` outputs."""
    T = np.array(SEED001_T_C)
    cols = {"T_ambient_C": T}
    if dT_K:
        for k in ("T_inner_ring_C", "T_outer_ring_C", "T_ball_C"):
            cols[k] = T + dT_K
    cols.update(columns or {})
    return simulate_table(asm, cols, effects, pipeline=Pipeline.shared(asm, mesh_factor=mesh_factor))


def seed001(mesh_factor: float = 1.0) -> PublishedAsData:
    """Every seed 001 candidate fitted on the cold ratio, the hot ratio held out."""
    asm = load_shipped("seed001")
    lo, hi = SEED001_COLD_BAND
    target = float(np.sqrt(lo * hi))
    tol = SEED001_REL_TOL * SEED001_HOT

    def ratios(cand: Candidate, v: float) -> tuple[float, float]:
        a, extra, eff = cand.setup(v)
        dT = float(extra.get("dT_K", 0.0))
        M = seed001_torques(a, None, eff, dT, mesh_factor)["torque_Nmm"]
        return float(M[0] / M[1]), float(M[2] / M[1])

    base = Candidate("as configured", "", (np.nan, np.nan), "", lambda v: (asm, {}, None))
    configured = ratios(base, np.nan)
    fits = tuple(_fit_one(c, ratios, target, SEED001_COLD_BAND, SEED001_HOT, tol)
                 for c in seed001_candidates(asm))
    return PublishedAsData("torque -20 C / 20 C", target, SEED001_COLD_BAND, "torque 60 C / 20 C",
                           SEED001_HOT, tol, configured, fits)


def self_heating_needed_K(mesh_factor: float = 1.0, upper_K: float = 150.0) -> float:
    """The bearing-above-chamber offset (K) that puts the cold ratio at the centre of the band
    when its bound is lifted (NaN if not reached below `upper_K`): what the data would ask for."""
    asm = load_shipped("seed001")
    target = float(np.sqrt(np.prod(SEED001_COLD_BAND)))

    def f(dT):
        M = seed001_torques(asm, None, None, dT, mesh_factor)["torque_Nmm"]
        return M[0] / M[1] - target
    return float(brentq(f, 0.0, upper_K, rtol=1e-6)) if f(0.0) * f(upper_K) < 0 else float("nan")


# --------------------------------------------------------------------------------- seed 000
def seed000_design() -> dict[str, np.ndarray]:
    """Five seed 000 cycles (`designs.cycles`), 5 min samples."""
    n = int(round(SEED000_CYCLES * SEED000_CYCLE_MIN * 60.0 / SEED000_DT_S))
    return cycle_design(n=n, dt=SEED000_DT_S)


def cycle_extremes(time_s: np.ndarray, torque_Nmm: np.ndarray) -> tuple[float, float]:
    """(max, min) change of the torque from the first cycle to the last one, N mm."""
    k = np.floor(np.asarray(time_s, float) / (60.0 * SEED000_CYCLE_MIN)).astype(int)
    first, last = torque_Nmm[k == 0], torque_Nmm[k == k.max()]
    return float(last.max() - first.max()), float(last.min() - first.min())


def seed000_candidates(asm: Assembly) -> list[Candidate]:
    """History candidates with one free parameter each (the others fixed as stated)."""
    P = float(asm.preload.assembled_N)
    return [
        Candidate("preload_settling (threshold 70 K)", "loss_N", (0.0, P),
                  f"0 to the assembled {P:g} N (a pair cannot lose more); the threshold between "
                  "the +60 K and -80 K excursions so that the first cycle's maximum precedes it",
                  lambda v: (asm, {}, {"preload_settling": {"loss_N": v, "threshold_K": 70.0}})),
        Candidate("preload_settling.creep (threshold 20 K, no step)", "creep_N_per_h",
                  _effect_bounds("preload_settling.creep", "creep_N_per_h"),
                  "effect bounds (effects/preload_settling_creep.py: VDI 2230 embedding and creep)",
                  lambda v: (asm, {}, {"preload_settling.creep": {"loss_N": 0.0, "threshold_K": 20.0,
                                                                  "creep_N_per_h": v}})),
        Candidate("solid_film_runin (10 krev)", "dmu", _effect_bounds("solid_film_runin", "dmu"),
                  "effect bounds (effects/solid_film_runin.py: Roberts 1990 MoS2 films)",
                  lambda v: (asm, {}, {"solid_film_runin": {"dmu": v, "runin_krev": 10.0}})),
        Candidate("preload path softened after the first cycle", "extra_compliance_um_per_kN",
                  _effect_bounds("preload_path_compliance", "extra_compliance_um_per_kN"),
                  "effect bounds (effects/preload_path_compliance.py: VDI 2230); embedding of the "
                  "clamped faces in the first cycle taken as a softer path, not a lost preload",
                  lambda v: (asm, {}, {"preload_path_compliance": {"extra_compliance_um_per_kN": v}}),
                  after_first_cycle=True),
    ]


def seed000(fit_on: str = "max", mesh_factor: float = 1.0) -> PublishedAsData:
    """The seed 000 history candidates fitted on the cycle-to-cycle change of the torque maximum
    (fit_on="max") or minimum ("min"), the other change held out."""
    asm = load_shipped("seed000")
    cols = seed000_design()
    pl = Pipeline.shared(asm, mesh_factor=mesh_factor)
    i_fit = 0 if fit_on == "max" else 1
    pub = (SEED000_MAX_CHANGE_NMM, SEED000_MIN_CHANGE_NMM)

    M0 = simulate_table(asm, cols, None, pipeline=pl)["torque_Nmm"]
    first = np.floor(cols["time_s"] / (60.0 * SEED000_CYCLE_MIN)) == 0

    def changes(cand: Candidate, v: float) -> tuple[float, float]:
        a, _, eff = cand.setup(v)
        M = simulate_table(a, cols, eff, pipeline=pl)["torque_Nmm"]
        if cand.after_first_cycle:     # the static model has no memory: the first cycle as built
            M = np.where(first, M0, M)
        ch = cycle_extremes(cols["time_s"], M)
        return ch[i_fit], ch[1 - i_fit]

    t = pub[i_fit]
    base = Candidate("as configured", "", (np.nan, np.nan), "", lambda v: (asm, {}, None))
    configured = changes(base, np.nan)
    fits = tuple(_fit_one(c, changes, t, (t - SEED000_TOL_NMM, t + SEED000_TOL_NMM), pub[1 - i_fit],
                          SEED000_TOL_NMM) for c in seed000_candidates(asm))
    names = ("torque max, steady - first cycle (N mm)", "torque min, steady - first cycle (N mm)")
    return PublishedAsData(names[i_fit], t, (t - SEED000_TOL_NMM, t + SEED000_TOL_NMM),
                           names[1 - i_fit], pub[1 - i_fit], SEED000_TOL_NMM, configured, fits)
