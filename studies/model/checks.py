"""Checks in every run: each operating point against the assembly's limits and the built-in
checks, as flag columns (`flag_<check>`, 1 = violated) and margins (`margin_<check>`,
allowable / actual - 1 for an upper limit, actual / allowable - 1 for a lower one; >= 0 is inside).

Checks and their allowables (docs/cli.md, "simulate: limits"):
- max_contact_pressure_MPa <= `[limits] max_contact_pressure_MPa`; without it the ISO 76:2006
  static limit of 4200 MPa (ball bearings, clause 3.1), said so in the summary;
- static_safety >= `[limits] min_static_safety`; without it 3 (GB/T 28878.2-2016 B.4, launch);
- preload_lost: the pair's preload must stay above 0 N (a bearing unloaded);
- fit_open_inner / fit_open_outer / fit_open_sleeve / fit_open_cartridge: the fit pressure must
  stay above 0 MPa, for a fit designed with interference only (the mean assembly at the reference
  temperature, `tolerances.designed_closed`; a fit designed as a clearance is not flagged for
  being open). The sleeve's and cartridge's fits are the fits on their outside. Its margin
  `margin_fit_<fit>_MPa` is the fit pressure left before the fit opens (MPa; value - 0 MPa, the
  same kind of margin as the clamp's in newtons); a designed clearance has neither;
- clamp_open (a `[nut]`/`[cover]` with clamp = "force" only): the clamp force left before a
  stack face opens, `margin_clamp_N` (N, `studies.model.stages.fe.ClampState`), must stay above
  0 N; its margin is that column in newtons (a strict check: no relative margin).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from analytic.safety import GBT_LAUNCH_SAFETY, ISO76_CONTACT_PRESSURE_MPa
from studies.model.inputs import PARTS
from studies.model.tolerances import designed_closed


#: every flag and margin column `simulate` may write (the checks of any assembly)
CHECK_COLUMNS = frozenset(
    [f"flag_{n}" for n in ("max_contact_pressure_MPa", "static_safety", "preload_lost",
                           "fit_open_inner", "fit_open_outer", "fit_open_sleeve",
                           "fit_open_cartridge")]
    + [f"margin_{n}" for n in ("max_contact_pressure_MPa", "static_safety")]
    + [f"margin_fit_{n}_MPa" for n in ("inner", "outer", "sleeve", "cartridge")]
    + ["flag_clamp_open", "margin_clamp_N"])                     # clamp = "force" only


@dataclass(frozen=True)
class Check:
    """One check: `value` of a result (per row, in `unit`) against `allowable`.
    name: flag_<name>, margin_<name>; column: the output column checked (docs/cli.md);
    upper: True for value <= allowable, False for value >= (strict: >) allowable; source: where
    the allowable comes from; value: the checked quantity of a `SimulationResult` (a module-level
    function, so that checks travel to Dask workers); strict: a lower limit of 0 that must be
    exceeded (no relative margin); margin_column: for a strict check, the column of its margin
    in its own unit (value - allowable), "" for none."""
    name: str
    column: str
    allowable: float
    upper: bool
    unit: str
    source: str
    value: Callable[[object], np.ndarray]
    strict: bool = False
    margin_column: str = ""


@dataclass(frozen=True)
class Violation:
    check: Check
    rows: np.ndarray          # 0-based rows violating it
    worst_row: int
    worst_value: float

    def summary(self, n_rows: int, conditions: dict | None = None) -> str:
        c = self.check
        at = f"row {self.worst_row + 1}"
        T = (conditions or {}).get("T_ambient_C")
        if T is not None:
            at += f", T_ambient_C = {float(np.asarray(T)[self.worst_row]):g}"
        rel = ">" if c.upper else ("<=" if c.strict else "<")
        return (f"{self.rows.size} of {n_rows} rows violate {c.name} (worst {self.worst_value:.4g} "
                f"{rel} {c.allowable:g} {c.unit} at {at}; limit: {c.source})")


@dataclass(frozen=True)
class CheckOutcome:
    """One check over the rows of a result. value: the checked quantity per row (check.unit);
    violated: bool per row; margin: allowable / value - 1 (upper limit) or value / allowable - 1
    (lower limit), >= 0 inside, inf where not finite (an unloaded row); for a strict check
    value - allowable in its unit where it names a `margin_column`, else None."""
    check: Check
    value: np.ndarray
    violated: np.ndarray
    margin: np.ndarray | None

    def violation(self) -> Violation | None:
        """The rows violating the check and the worst of them (the first of equal worst values),
        or None."""
        if not self.violated.any():
            return None
        v, rows = self.value, np.flatnonzero(self.violated)
        worst = int(rows[np.argmax(v[rows])] if self.check.upper else rows[np.argmin(v[rows])])
        return Violation(self.check, rows, worst, float(v[worst]))


@dataclass(frozen=True)
class Checks:
    """Every check of an assembly (`assembly_checks`) over the rows of a result, in order."""
    outcomes: tuple[CheckOutcome, ...]

    def violations(self) -> list[Violation]:
        """The violated checks (0-based rows of this result)."""
        return [v for v in (o.violation() for o in self.outcomes) if v is not None]


def _max_contact_pressure_MPa(result) -> np.ndarray:
    return result.pair.max_contact_pressure_MPa


def _static_safety(result) -> np.ndarray:
    return result.summary.static_safety


def _preload_N(result) -> np.ndarray:
    return result.pair.preload_N


def _fit_pressure_inner_MPa(result) -> np.ndarray:
    return result.fits.inner_MPa


def _fit_pressure_outer_MPa(result) -> np.ndarray:
    return result.fits.outer_MPa


def _fit_pressure_sleeve_MPa(result) -> np.ndarray:
    return result.fits.layer_MPa("sleeve")


def _fit_pressure_cartridge_MPa(result) -> np.ndarray:
    return result.fits.layer_MPa("cartridge")


_FIT_PRESSURE = {"inner": _fit_pressure_inner_MPa, "outer": _fit_pressure_outer_MPa,
                 "sleeve": _fit_pressure_sleeve_MPa, "cartridge": _fit_pressure_cartridge_MPa}


def fit_pressure_MPa(result, fit: str) -> np.ndarray:
    """(n,) pressure (MPa) of one fit (inner, outer, sleeve, cartridge) as the fit_open check
    reads it (`design` counts every fit by it)."""
    return _FIT_PRESSURE[fit](result)


def _margin_clamp_N(result) -> np.ndarray:
    return result.clamp.margin_N


def assembly_checks(asm) -> list[Check]:
    """The checks that apply to an assembly, with their allowables and sources."""
    lim = asm.limits
    p_max = lim.max_contact_pressure_MPa
    checks = [
        Check("max_contact_pressure_MPa", "max_contact_pressure_MPa",
              p_max if np.isfinite(p_max) else ISO76_CONTACT_PRESSURE_MPa, True, "MPa",
              "[limits] max_contact_pressure_MPa" if np.isfinite(p_max)
              else "ISO 76 static limit, no [limits] value given", _max_contact_pressure_MPa),
        Check("static_safety", "static_safety",
              lim.min_static_safety if lim.min_static_safety > 0 else GBT_LAUNCH_SAFETY, False,
              "", "[limits] min_static_safety" if lim.min_static_safety > 0
              else "GB/T 28878.2 B.4 default, no [limits] value given", _static_safety),
        Check("preload_lost", "preload_N", 0.0, False, "N", "a preloaded pair", _preload_N,
              strict=True)]
    for side, closed in designed_closed(asm).items():
        if closed:                        # a designed clearance is allowed to be open
            checks.append(Check(f"fit_open_{side}", f"fit_pressure_{side}_MPa", 0.0, False, "MPa",
                                "a fit assembled with interference", _FIT_PRESSURE[side],
                                strict=True, margin_column=f"margin_fit_{side}_MPa"))
    if "force" in (asm.nut.clamp, asm.cover.clamp):
        checks.append(Check("clamp_open", "margin_clamp_N", 0.0, False, "N",
                            'the clamp force left before a stack face opens (clamp = "force")',
                            _margin_clamp_N, strict=True))
    return checks


def evaluate_checks(result, checks: list[Check]) -> Checks:
    """Every check over the rows of `result` (a `SimulationResult`, or whatever the checks'
    `value` functions read)."""
    outcomes = []
    for c in checks:
        v = np.asarray(c.value(result), float)
        with np.errstate(divide="ignore", invalid="ignore"):     # an unloaded row: infinite margin
            if c.upper:
                bad = v > c.allowable
                margin = c.allowable / v - 1.0 if not c.strict else None
            else:
                bad = v <= c.allowable if c.strict else v < c.allowable
                margin = v / c.allowable - 1.0 if not c.strict else None
        if margin is not None:
            margin = np.where(np.isfinite(margin), margin, np.inf)
        if c.margin_column:                           # a margin in the check's own unit
            margin = v - c.allowable
        outcomes.append(CheckOutcome(c, v, bad, margin))
    return Checks(tuple(outcomes))


# ---------------------------------------------------------------------- plausibility warnings
#: viscous / load torque above which f0 is questioned: Palmgren's f0 spans ~0.7 (little grease) to
#: 4+ (oil bath) (Harris & Kotzalas Vol. 1 ch. 9), a factor ~6 in the viscous term; a ratio this
#: large means the viscous term decides everything and the lubrication amount must be known
VISCOUS_TO_LOAD_WARN = 50.0
#: lubrication methods for which the oil-bath f0 is the right one (no warning on it); the warning
#: is Palmgren's f0's only (the other laws' viscous terms do not take f0 as stated: skf2004 its
#: own rolling term, ehl_rolling the contacts', starved and minimal_oil f0 times the oil's factor)
BATH_OR_JET = ("oil_bath", "oil_jet", "oil_air")

#: a clamp's given spring below this fraction of its thread's own stiffness (VDI 2230 default)
#: is warned about: the force clamp is then the compliant limit, tightened by an overlap of
#: F / k, and the round-off of the contact problem grows as k_thread / k
CLAMP_SOFT_WARN = 1e-4


def _soft_clamp_warnings(asm) -> list[str]:
    """One line per clamp with a force whose `clamp_stiffness_N_per_um` is below CLAMP_SOFT_WARN
    of the stiffness its section gives (`studies.model.stack.clamp_stiffness_N_per_mm`)."""
    from dataclasses import replace

    from studies.model.stack import clamp_stiffness_N_per_mm

    msgs = []
    for name in ("nut", "cover"):
        c = getattr(asm, name)
        if c.clamp != "force" or not c.clamp_stiffness_N_per_um > 0:
            continue
        own = clamp_stiffness_N_per_mm(replace(asm, **{name: replace(c, clamp_stiffness_N_per_um=0.0)}),
                                       name)
        k = 1e3 * c.clamp_stiffness_N_per_um
        if k < CLAMP_SOFT_WARN * own:
            msgs.append(f"{name}.clamp_stiffness_N_per_um = {c.clamp_stiffness_N_per_um:g} is "
                        f"{k / own:.1e} of its thread's own stiffness ({own / 1e3:.4g} N/um, VDI "
                        f"2230): a spring that soft is the compliant limit, tightened by "
                        f"{c.clamp_force_N / k:.3g} mm, and makes the contact problem "
                        f"ill-conditioned (round-off x {own / k:.1e})")
    return msgs


#: a condition temperature (C) above this is no bearing's operating point: a unit typed wrong
#: (assumption: above the highest temperature a standard bearing-steel ring is dimensionally
#: stabilised for, S0 = 150 C, DIN 623-1, and far above every seed's range)
FAHRENHEIT_HOT_C = 150.0
#: how far (K) outside [operating] T_min_C..T_max_C a condition column must reach, and how
#: near it its values read as Fahrenheit must fall, for the Fahrenheit warning
FAHRENHEIT_FAR_K = 20.0


def _fahrenheit_warnings(asm, conditions: dict) -> list[str]:
    """One line for the first T_*_C condition column that looks like Fahrenheit: it reaches
    FAHRENHEIT_FAR_K above [operating] T_max_C and, read as Fahrenheit ((v - 32) / 1.8, NIST
    SP 811 B.8), lies inside the operating range widened by FAHRENHEIT_FAR_K; or any value above
    FAHRENHEIT_HOT_C."""
    op = asm.operating
    for c, v in conditions.items():
        v = np.asarray(v, float)
        v = v[np.isfinite(v)]
        if not (c.startswith("T_") and c.endswith("_C")) or not v.size:
            continue
        hi, as_C = float(v.max()), (v - 32.0) / 1.8
        looks_F = (hi > op.T_max_C + FAHRENHEIT_FAR_K and as_C.min() >= op.T_min_C - FAHRENHEIT_FAR_K
                   and as_C.max() <= op.T_max_C + FAHRENHEIT_FAR_K)
        if looks_F or hi > FAHRENHEIT_HOT_C:
            return [f"conditions column {c}: {v.min():g}..{hi:g} C reaches {hi - op.T_max_C:.0f} K "
                    f"above [operating] T_max_C = {op.T_max_C:g} C; read as Fahrenheit it is "
                    f"{as_C.min():.1f}..{as_C.max():.1f} C: Fahrenheit typed as Celsius?"]
    return []


def plausibility_warnings(asm, conditions: dict | None = None, out: dict | None = None) -> list[str]:
    """Legal but implausible inputs and results, one line each (the run goes on):
    units typed wrong (kelvin for Celsius, radians for degrees, mm for um), a viscous torque
    that dwarfs the load torque (an oil-bath Palmgren f0 on a lightly lubricated bearing) and a
    contact ellipse truncated by the land (`analytic/bearing/land.py`) and a clamp's spring
    so soft it is ill-conditioned (`CLAMP_SOFT_WARN`)."""
    msgs = []
    b, f = asm.bearing, asm.fits
    if b.contact_angle_free_deg < np.pi / 2:             # 1.57: a right angle in radians
        msgs.append(f"bearing.contact_angle_free_deg = {b.contact_angle_free_deg:g} deg looks like "
                    "radians (an angular-contact bearing has 10-40 deg)")
    for key, v in (("fits.inner_interference_um", f.inner_interference_um),
                   ("fits.outer_interference_um", f.outer_interference_um),
                   *((f"fits.{n}_interference_um", getattr(f, f"{n}_interference_um"))
                     for n, _ in asm.layers())):
        if 0.0 < abs(v) < 0.1:
            msgs.append(f"{key} = {v:g} um looks like millimetres (bearing fits are a few um)")
    if asm.T_ref_C > 200.0:
        msgs.append(f"assembly.T_ref_C = {asm.T_ref_C:g} C looks like kelvin")
    for c, v in (conditions or {}).items():
        if c.startswith("T_") and c.endswith("_C") and np.size(v) and np.min(v) > 200.0:
            msgs.append(f"conditions column {c}: every value above 200 C (min {np.min(v):g}): "
                        "kelvin typed as Celsius?")
            break
    else:
        msgs += _fahrenheit_warnings(asm, conditions or {})
    if conditions is not None and asm.thermal.mode == "given" and "T_ambient_C" not in conditions:
        bare = [p for p in PARTS if f"T_{p}_C" not in conditions]
        if bare:
            msgs.append(f"conditions: no column T_ambient_C: {', '.join(bare)} at the default, "
                        f"assembly.T_ref_C = {asm.T_ref_C:g} C, in every row")
    th = asm.thermal
    if th.mode == "transient" and not th.films and th.emissivity == 0:
        msgs.append("thermal: no [thermal.films] and emissivity 0: the stack is adiabatic outside; "
                    "T_ambient_C sets only its starting temperature and every watt of the "
                    "bearing's heat stays in it (the temperatures rise without bound)")
    lub = asm.lubrication
    f0_law = lub.viscous_model == "palmgren" and lub.lubrication_method not in BATH_OR_JET
    if f0_law and out is not None and "torque_viscous_Nmm" in out and "torque_load_Nmm" in out:
        visc = np.asarray(out["torque_viscous_Nmm"], float)
        load = np.asarray(out["torque_load_Nmm"], float)
        loaded = load > 0.0                 # rows with preload lost are flagged elsewhere
        ratio = float(np.max(visc[loaded] / load[loaded])) if loaded.any() else 0.0
        if ratio > VISCOUS_TO_LOAD_WARN:
            msgs.append(f"viscous torque up to {ratio:.0f}x the load torque: Palmgren f0 = "
                        f"{asm.lubrication.viscous_factor_f0:g} is an oil-bath value; a bearing with "
                        "a few milligrams of oil runs far below it")
    oil = asm.oil()
    if oil is not None and out is not None and "viscosity_mm2_s" in out:
        # the oil temperature of each row from its viscosity through the unscaled law (exact
        # without the viscosity_temperature effect, which moves the law about 40 C)
        law = oil.walther()
        if (msg := law.extrapolation_warning(out["viscosity_mm2_s"], oil.name)) is not None:
            msgs.append(msg)
    msgs += _soft_clamp_warnings(asm)
    for side in ("inner", "outer"):
        m = None if out is None else out.get(f"land_margin_{side}_deg")
        if m is not None and np.any(np.asarray(m) < 0):
            m = np.asarray(m, float)
            i = int(np.argmin(m))
            msgs.append(f"{side} contact ellipse truncated by the land in {int((m < 0).sum())} of "
                        f"{m.size} rows (up to {-m[i]:.3g} deg beyond the groove edge at row "
                        f"{i + 1}): the edge carries load the Hertz pressure does not describe"
                        + ("" if getattr(asm.bearing, f"{side}_land_diameter_mm") > 0 else
                           f" (land diameter inferred from the effective ring section; give "
                           f"[bearing] {side}_land_diameter_mm from the bearing's drawing)"))
    return msgs
