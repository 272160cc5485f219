"""Thermal histories made another way: part temperatures from the independent
conduction network of the stack (`studies.validation.conduction_network`, not the tool's
transient FE), run through plain `simulate` (the one route, `second_source._run`: the
pipeline of the diagnosed assembly, the rig's friction MU_TRUE x the configured one), with
realistic noise, and given to `diagnose` with only `time_s`, `T_ambient_C` (and `speed_rpm`)
beside the measured `preload_N` and `torque_Nmm`.

Cases (`CASES`): seed 000's stack on its -60..80 C cycles (`designs.cycles`, 240 x 120 s) in
forced air, still air, vacuum with radiation, and bolted to an aluminium plate in forced air;
seed 000 on a speed staircase (2000 / 1000 / 3000 rpm on the chamber steps 0..60 C of
`designs.speed_steps`) in still air with the bearing's own friction heat; seed 001's hybrid pair
at 300 rpm on the cycles in forced air with its friction heat; two causes beside a
thermal history: a 12 N preload loss (a step of the assembled preload when the chamber first
reaches its cold extreme) and a 12 N settling (exponential over 1 h from the first hot
excursion), both on the bolted stack; and the forced-air case with a torque sensor whose noise
is 1.5 % of reading.

Noise (`second_source.add_noise`): of the stated level sigma (`second_source.stated_sigma`, 1 %
of the column's mean absolute value), a white part of 0.8 sigma plus an AR(1) part of 0.6 sigma
with phi 0.8 per 120 s row (marginal standard deviation sqrt(0.64 + 0.36) sigma = sigma); the
percent-of-reading case draws the torque's noise as 1.5 % x |torque| x N(0, 1) instead.

Judged by `second_source.judge_result`. Run: `python -m studies.validation.thermal_history
--draws 2` prints the confusion table (outcome per case over the draws).
"""
from __future__ import annotations

import argparse
import math
import time
from dataclasses import dataclass, replace

import numpy as np

from studies.diagnosis.designs import cycles, speed_steps
from studies.validation import second_source as ss
from studies.validation.conduction_network import (ENVIRONMENTS, BearingHeat,
                                                   conduction_temperatures)

#: the thermal family: a diagnosis that names any of these names the thermal history
#: (`second_source.family` of the cause: `thermal_lag.per_part` is `thermal_lag`)
THERMAL = ("thermal_lag", "radial_gradient", "thermal_transient_fe")
#: a preload loss or settling beside the history
SETTLING = ("preload_settling",)
#: the stated noise split: white share and AR(1) share of sigma (shares of the variance 0.64 +
#: 0.36 = 1) and the AR(1) coefficient per row
WHITE_SHARE, AR_SHARE, AR_PHI = 0.8, 0.6, 0.8
#: percent-of-reading torque noise of a transducer (HBM T22 class 0.5 at low range: 1.5 %)
TORQUE_READING_SHARE = 0.015
#: the preload loss beside a history (N): about 9 sigma of seed 000's 1 % noise
PRELOAD_LOSS_N = 12.0
#: the settling's time constant (s) after the first hot excursion
SETTLING_TAU_S = 3600.0
#: shells per part of the conduction network (`conduction_network.stack_network`): within
#: 1e-3 K of the converged field (tests/test_conduction_network.py)
SHELLS = 4


#: speeds of seed 000's staircase (rpm): a space mechanism run up in steps, not monotone in time
#: (`designs.SPEEDS_RPM`'s reason); its MoS2 pair makes 0.15..0.47 W there
STAIRCASE_RPM = (2000.0, 1000.0, 3000.0)
#: seed 001's constant speed in its thermal cycles (rpm): 0.67 W of friction heat at 20 C
SEED001_RPM = 300.0

#: design -> (shipped assembly key, the conditions given): seed 000's cycles; seed 000's speed
#: staircase on the chamber steps 0..60 C of `designs.speed_steps`; seed 001 on the cycles at a
#: constant SEED001_RPM
DESIGNS = {
    "cycles": ("seed000", cycles),
    "speed_staircase": ("seed000", lambda: speed_steps(speeds_rpm=STAIRCASE_RPM)),
    "seed001_cycles": ("seed001", lambda: cycles(speeds_rpm=(SEED001_RPM,))),
}


@dataclass(frozen=True)
class HistoryCase:
    """What a thermal-history case is: design (DESIGNS), environment (ENVIRONMENTS), whether the
    bearing's friction heat drives the network, the second cause ("" / "preload_step" /
    "settling"), the noise ("stated" / "reading"), the truth labels, the causes a diagnosis may
    name and be right, and a text."""
    design: str
    env: str
    heat: bool
    second: str
    noise: str
    truth: tuple[str, ...]
    right: tuple[str, ...]
    text: str


CASES: dict[str, HistoryCase] = {
    "th_forced_air": HistoryCase(
        "cycles", "forced_air", False, "", "stated", ("thermal_lag",), THERMAL,
        "seed 000 in a climate chamber with its fan (2 m/s across the housing)"),
    "th_still_air": HistoryCase(
        "cycles", "still_air", False, "", "stated", ("thermal_lag",), THERMAL,
        "seed 000 in still air (natural convection)"),
    "th_vacuum": HistoryCase(
        "cycles", "vacuum", False, "", "stated", ("thermal_lag",), THERMAL,
        "seed 000 in thermal vacuum, radiation only (emissivity 0.8, shroud at the set point)"),
    "th_mount": HistoryCase(
        "cycles", "mount_forced_air", False, "", "stated", ("thermal_lag",), THERMAL,
        "seed 000 bolted to a 150 x 150 x 10 mm aluminium plate in forced air"),
    "th_speed_staircase": HistoryCase(
        "speed_staircase", "still_air", True, "", "stated", ("thermal_lag",), THERMAL,
        "seed 000 on a speed staircase (2000 / 1000 / 3000 rpm) and chamber steps 0..60 C in "
        "still air, heated by its own friction"),
    "th_seed001_forced_air": HistoryCase(
        "seed001_cycles", "forced_air", True, "", "stated", ("thermal_lag",), THERMAL,
        f"seed 001's hybrid pair at {SEED001_RPM:g} rpm on the -60..80 C cycles in forced air, "
        "heated by its own friction"),
    "th_mount_preload_loss": HistoryCase(
        "cycles", "mount_forced_air", False, "preload_step", "stated",
        ("thermal_lag", "preload_settling"), THERMAL + SETTLING,
        f"the bolted stack and a {PRELOAD_LOSS_N:g} N loss of the assembled preload when the "
        "chamber first reaches -60 C"),
    "th_mount_settling": HistoryCase(
        "cycles", "mount_forced_air", False, "settling", "stated",
        ("thermal_lag", "preload_settling"), THERMAL + SETTLING,
        f"the bolted stack and a {PRELOAD_LOSS_N:g} N settling of the preload over "
        f"{SETTLING_TAU_S:g} s from the first excursion beyond 50 K"),
    "th_forced_air_reading_noise": HistoryCase(
        "cycles", "forced_air", False, "", "reading", ("thermal_lag",), THERMAL,
        f"seed 000 in forced air, torque noise {100 * TORQUE_READING_SHARE:g} % of reading"),
}


#: the grid of the bearing's temperature for its heat (`bearing_heat`): from HEAT_BELOW_K under
#: the lowest ambient to HEAT_ABOVE_K over the highest, every HEAT_STEP_K (held beyond)
HEAT_BELOW_K, HEAT_ABOVE_K, HEAT_STEP_K = 20.0, 120.0, 5.0


def bearing_heat(asm, speed_rpm: np.ndarray, T_ambient_C: np.ndarray,
                 mesh_factor: float = 1.0) -> BearingHeat:
    """The pair's friction heat (W) at the bearing's own temperature
    (`conduction_network.BearingHeat`): torque (N mm, the project's own friction model through
    the one route, `second_source._run`, the rig's friction MU_TRUE, every part at the grid's
    temperature) x omega, P = M omega (Harris & Kotzalas vol. 2 ch. 7), at each distinct speed
    and each temperature of the grid (HEAT_*_K). The network feeds it at its rings' and balls'
    temperature at every instant: the energy put into the stack is what the rows' torque
    dissipates (an oil's viscous heat falls tenfold or more from -60 C to 20 C)."""
    speeds, row_set = np.unique(np.asarray(speed_rpm, float), return_inverse=True)
    amb = np.asarray(T_ambient_C, float)
    lo = float(amb.min()) - HEAT_BELOW_K
    grid = lo + HEAT_STEP_K * np.arange(int(np.ceil((float(amb.max()) + HEAT_ABOVE_K - lo)
                                                    / HEAT_STEP_K)) + 1)
    cond = {"T_ambient_C": np.tile(grid, speeds.size), "speed_rpm": np.repeat(speeds, grid.size)}
    torque = ss._run(asm, mesh_factor, cond)["torque_Nmm"]
    heat = torque * 1e-3 * cond["speed_rpm"] * 2.0 * math.pi / 60.0
    return BearingHeat(grid, np.log(np.maximum(heat, 1e-12)).reshape(speeds.size, grid.size),
                       row_set.reshape(-1), np.zeros(0))


def _preload_history(spec: HistoryCase, asm, cond) -> np.ndarray | None:
    """The assembled preload per row of the truth (N) for the case's second cause, or None."""
    t, amb = cond["time_s"], cond["T_ambient_C"]
    P0 = asm.preload.assembled_N
    if spec.second == "preload_step":
        k = int(np.argmax(amb <= amb.min() + 1e-9))
        return np.where(np.arange(t.size) >= k, P0 - PRELOAD_LOSS_N, P0)
    if spec.second == "settling":
        k = int(np.argmax(np.abs(amb - asm.T_ref_C) > 50.0))
        dt = np.clip(t - t[k], 0.0, None)
        return P0 - PRELOAD_LOSS_N * np.where(t >= t[k], 1.0 - np.exp(-dt / SETTLING_TAU_S), 0.0)
    return None


#: noise-free truths by (case, mesh factor): the same for every draw
_TRUTH: dict[tuple, tuple] = {}


def _truth(name: str, mesh_factor: float):
    from studies.model.config import load_shipped

    spec = CASES[name]
    key, make = DESIGNS[spec.design]
    asm = load_shipped(key)
    cond = {k: np.asarray(v, float) for k, v in make().items()}
    heat = (bearing_heat(asm, cond["speed_rpm"], cond["T_ambient_C"], mesh_factor) if spec.heat
            else 0.0)
    # (without heat the pair turns at the configured speed: seed 000's 60 rpm make 0.01 W)
    hist = conduction_temperatures(asm, cond["time_s"], cond["T_ambient_C"], ENVIRONMENTS[spec.env],
                                   heat, SHELLS)
    rows = {**cond, **hist.columns}
    P = _preload_history(spec, asm, cond)
    if P is not None:
        rows["preload_assembled_N"] = P
    truth = ss._run(asm, mesh_factor, rows)
    sigma = ss.stated_sigma(truth)
    ch = ss.change_sigma(asm, cond, truth, sigma, mesh_factor)
    return asm, cond, truth, sigma, ch, hist


def make_case(name: str, seed: int = 0, mesh_factor: float = 1.0) -> ss.Case:
    """One draw of a thermal-history case as a `second_source.Case` (its conditions only the
    design's `time_s`, `T_ambient_C`, `speed_rpm`; measured `torque_Nmm`, `preload_N`)."""
    spec = CASES[name]
    key = (name, float(mesh_factor))
    if key not in _TRUTH:
        _TRUTH[key] = _truth(name, mesh_factor)
    asm, cond, truth, sigma, ch, _ = _TRUTH[key]
    rng = np.random.default_rng([seed, sum(map(ord, name))])
    t = cond["time_s"]
    white = ss.Noise(sigma={c: WHITE_SHARE * s for c, s in sigma.items()})
    ar = ss.Noise(sigma={c: AR_SHARE * s for c, s in sigma.items()}, phi=AR_PHI)
    zero = {c: np.zeros_like(v) for c, v in truth.items()}
    e_white, _ = ss.add_noise(zero, white, rng, t)
    e_ar, _ = ss.add_noise(zero, ar, rng, t)
    measured = {c: truth[c] + e_white[c] + e_ar[c] for c in truth}
    noise = ss.Noise(sigma=dict(sigma), phi=AR_PHI)
    if ENVIRONMENTS[spec.env].gas == "vacuum":
        # a thermal-vacuum test is run in vacuum and its file says so (`[thermal] gas`): what
        # the user knows of the chamber; its emissivity is left to the fit
        asm = replace(asm, thermal=replace(asm.thermal, gas="vacuum"))
    if spec.noise == "reading":
        v = truth["torque_Nmm"]
        measured["torque_Nmm"] = v + TORQUE_READING_SHARE * np.abs(v) * rng.normal(size=v.size)
    return ss.Case(name, "history" if len(spec.truth) == 1 else "multiple", spec.design, seed,
                   spec.truth, spec.right, asm, dict(cond), measured,
                   {c: v.copy() for c, v in truth.items()}, dict(sigma), noise, ch, spec.text,
                   mesh_factor=float(mesh_factor))


def stated_noise(name: str) -> dict | None:
    """The noise a user states for the case's sensors (`diagnose --noise`): the torque
    transducer's TORQUE_READING_SHARE of reading on the percent-of-reading case (its data
    sheet's statement, `torque_Nmm=1.5%`), else None (estimated from the data)."""
    from studies.diagnosis.noisemodel import StatedNoise

    if CASES[name].noise != "reading":
        return None
    return {"torque_Nmm": StatedNoise("stated", rel=TORQUE_READING_SHARE)}


@dataclass(frozen=True)
class Trial:
    """One diagnosed draw: case, seed, outcome (`second_source.OUTCOMES`), verdict, the named
    causes, the rivals, the case's change (sigma), the wall time of the diagnosis (s)."""
    case: str
    seed: int
    outcome: str
    verdict: str
    causes: tuple[str, ...]
    rivals: tuple[str, ...]
    change_sigma: float
    seconds: float


def run_trial(name: str, seed: int, workers: int = 1) -> Trial:
    """Diagnose one draw as `bearingfem diagnose` does (`second_source.diagnose_case`) and
    judge it (`second_source.judge_result`)."""
    case = make_case(name, seed)
    t0 = time.perf_counter()
    res = ss.diagnose_case(case, workers=workers, noise_model=stated_noise(name))
    dt = time.perf_counter() - t0
    return Trial(name, seed, ss.judge_result(case, res), res.verdict,
                 tuple(ss.named_causes(res)), tuple(res.indistinguishable), case.change_sigma, dt)


#: outcomes that name the cause ("named": explained, explained partly, ambiguous
#: with the thermal family)
NAMED = ("right", "named", "partial")


def table(trials: list[Trial]) -> str:
    """The confusion table: one line per case, the count of each outcome over its draws."""
    cols = ("right", "named", "partial", "unexplained", "missed", "false_alarm", "wrong")
    lines = [f"{'case':30s} {'change':>7s} " + " ".join(f"{c[:7]:>7s}" for c in cols)]
    for name in dict.fromkeys(t.case for t in trials):
        mine = [t for t in trials if t.case == name]
        lines.append(f"{name:30s} {mine[0].change_sigma:7.1f} "
                     + " ".join(f"{sum(t.outcome == c for t in mine):7d}" for c in cols))
    named = sum(t.outcome in NAMED for t in trials)
    lines.append(f"named {named} of {len(trials)}; wrong {sum(t.outcome == 'wrong' for t in trials)}")
    return "\n".join(lines)


def second_cause_rate(trials: list[Trial]) -> float:
    """Share of the two-cause draws whose named causes include the preload settling family."""
    two = [t for t in trials if len(CASES[t.case].truth) > 1]
    if not two:
        return math.nan
    return sum(any(ss.family(c) in SETTLING for c in t.causes) for t in two) / len(two)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--draws", type=int, default=2)
    ap.add_argument("--cases", nargs="*", default=list(CASES))
    ap.add_argument("--workers", type=int, default=1)
    a = ap.parse_args(argv)
    trials = []
    for name in a.cases:
        for seed in range(a.draws):
            tr = run_trial(name, seed, a.workers)
            trials.append(tr)
            print(f"{name} seed {seed}: {tr.outcome} ({tr.verdict}; {', '.join(tr.causes) or '-'}"
                  f"; rivals {', '.join(tr.rivals) or '-'}) change {tr.change_sigma:.1f} sigma,"
                  f" {tr.seconds:.1f} s", flush=True)
    print(table(trials))
    print(f"second cause named in {second_cause_rate(trials):.0%} of the two-cause draws")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
