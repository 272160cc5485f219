"""A sensor's stated noise (`diagnose --noise COLUMN=REL%[+ABS]`, per-row
`sigma_<column>`) is the likelihood's weights, its level checked against the data.

Checked against what does not come from the code under test: the closed-form weighted
least-squares estimate of a straight proportionality (Draper & Smith, Applied Regression
Analysis, 3rd ed., ch. 9.2), the chi-square law of a variance estimate (Monte Carlo rate of
false rejection against the stated 1 %), and bad input refused with one line before any FE work.
The slow test: a lag made by a first-order filter of this file (not the effect code) on the
flywheel rig whose torque spans more than two decades, with 1.5 % of reading noise.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from studies.app.cli import main
from studies.diagnosis.calibration import calibrate
from studies.diagnosis.noisemodel import (CONSISTENCY_ALPHA, NoiseSpecError, StatedNoise,
                                          consistency, parse_noise_arg, parse_noise_spec)
from studies.diagnosis.problem import make_problem
from studies.diagnosis.stats import noise_sigma
from studies.model.config import CONFIG_DIR

NUISANCE = {"mu_scale": (0.3, 3.0, 1.0, 0.05)}


def test_noise_spec_forms_and_refusals():
    """REL%+ABS, REL% and ABS as docs/cli.md states them; anything else one line naming the
    flag and its value."""
    s = parse_noise_spec("torque_Nmm", "1.5%+0.2")
    assert (s.source, s.rel, s.abs_unit) == ("stated", 0.015, 0.2)
    assert parse_noise_spec("torque_Nmm", "1.5%").abs_unit == 0.0
    assert parse_noise_spec("preload_N", "0.5").rel == 0.0
    assert parse_noise_spec("preload_N", 0.5).abs_unit == 0.5
    assert np.allclose(s.row_sigma(np.array([100.0, -1000.0])), [1.7, 15.2])
    for bad in ("abc", "1.5%+", "%", "-1%", "1.5%-0.2", "0", "0%+0"):
        with pytest.raises(NoiseSpecError, match=r"^--noise torque_Nmm="):
            parse_noise_spec("torque_Nmm", bad)
    assert parse_noise_arg("torque_Nmm=1.5%+0.2") == ("torque_Nmm", "1.5%+0.2")
    with pytest.raises(NoiseSpecError, match="need COLUMN="):
        parse_noise_arg("torque_Nmm")


def _proportional(n=120, seed=0):
    """y = 2 x with per-row noise 1.5 % of the reading y plus 0.2 (x over two decades), as a
    diagnosis problem whose only fitted parameter is the nuisance scale (the model
    mu_scale x x)."""
    rng = np.random.default_rng(seed)
    x = np.geomspace(100.0, 20000.0, n)
    s = 0.015 * 2.0 * x + 0.2
    y = 2.0 * x + s * rng.standard_normal(n)
    cond = {"T_ambient_C": np.linspace(-20.0, 60.0, n)}

    def predict(effects, nuisance):
        return {"torque_Nmm": nuisance["mu_scale"] * x}
    return x, y, s, cond, predict


def test_stated_weights_give_the_closed_form_weighted_least_squares_estimate():
    """With per-row sigma_<column> s_i the fitted scale is the weighted least-squares estimate
    sum(x y / s^2) / sum(x^2 / s^2) (Draper & Smith ch. 9.2) to the solver's tolerance
    (relative 1e-6 of the estimate), and without a statement the ordinary one sum(x y) /
    sum(x^2); the two differ here by a thousand times that tolerance, so the test tells them
    apart."""
    x, y, s, cond, predict = _proportional()
    wls = float(np.sum(x * y / s ** 2) / np.sum(x ** 2 / s ** 2))
    ols = float(np.sum(x * y) / np.sum(x ** 2))
    assert abs(ols - wls) > 1e-3 * wls
    for stated, expect in (({"torque_Nmm": StatedNoise("column", rows=s)}, wls), (None, ols)):
        pb = make_problem(predict, {"torque_Nmm": y}, cond, [], NUISANCE, noise_model=stated)
        space = pb.space([])
        fit = pb.fit(space, np.zeros(space.lo.size))
        got = space.unpack(fit.u)[1]["mu_scale"]
        assert got == pytest.approx(expect, rel=1e-6)


def test_calibration_checks_a_stated_level_against_the_data():
    """The calibrated noise of a column stated as 1.5 % + 0.2 (the truth) is consistent, its
    level within 30 % of the stated one (120 entries: the estimate's standard deviation is
    about 9 %, 30 % is 3 of them); stated 3 x too low or too high it is reported inconsistent,
    the weights' shape kept and the level the data's (within 30 % of the truth's)."""
    x, y, s, cond, predict = _proportional(seed=3)
    truth = float(np.sqrt(np.mean(s ** 2)))
    for factor, ok in ((1.0, True), (1.0 / 3.0, False), (3.0, False)):
        st = StatedNoise("stated", rel=0.015 * factor, abs_unit=0.2 * factor)
        pb = make_problem(predict, {"torque_Nmm": y}, cond, [], NUISANCE,
                          noise_model={"torque_Nmm": st})
        pb, _ = calibrate(pb)
        chk = pb.noise.consistency["torque_Nmm"]
        assert chk.consistent is ok, (factor, chk)
        assert chk.ratio == pytest.approx(1.0 / factor, rel=0.3)
        assert pb.noise.sigma["torque_Nmm"] == pytest.approx(truth, rel=0.3)
        assert pb.row_sigma("torque_Nmm") == pytest.approx(s / s.mean() * pb.row_sigma(
            "torque_Nmm").mean(), rel=0.05)


def test_consistency_rejects_the_right_statement_at_its_stated_rate():
    """1000 draws of 100 entries of noise 1.5 % of a reading over two decades, estimated as the
    calibration does (second differences of the residual divided by the stated shape): the true
    statement is refused in CONSISTENCY_ALPHA (1 %) of the draws (binomial standard deviation
    0.31 %: between 0.2 % and 2 %), a statement 3 x off in either
    direction in every draw."""
    rng = np.random.default_rng(1)
    n, draws = 100, 1000
    x = np.geomspace(100.0, 20000.0, n)
    s = 0.015 * x
    level = float(np.sqrt(np.mean(s ** 2)))
    seg = np.zeros(n, int)
    ratio = np.array([noise_sigma(s * rng.standard_normal(n) / (s / level), seg) / level
                      for _ in range(draws)])
    unit = consistency(1.0, n)          # the interval of a ratio r is r x that of 1
    assert consistency(0.8, n).ratio_lo == pytest.approx(0.8 * unit.ratio_lo, rel=1e-12)

    def refused(r):
        return (r * unit.ratio_lo > 1.0) | (r * unit.ratio_hi < 1.0)
    assert 0.002 <= refused(ratio).mean() <= 0.02 and CONSISTENCY_ALPHA == 0.01
    assert refused(3.0 * ratio).all() and refused(ratio / 3.0).all()


SEED000 = CONFIG_DIR / "seed000_71807C_TC4.toml"


def _measured_csv(tmp_path, sigma=None):
    n = 12
    rows = ["time_s,T_ambient_C,torque_Nmm" + (",sigma_torque_Nmm" if sigma is not None else "")]
    for i in range(n):
        rows.append(f"{60 * i},{20 + i},{100 + i}" + (f",{sigma[i]}" if sigma is not None else ""))
    f = tmp_path / "m.csv"
    f.write_text("\n".join(rows) + "\n")
    return f


@pytest.mark.parametrize("args, sigma, message", [
    (["--noise", "torque_Nmm=abc"], None, "--noise torque_Nmm=abc: not REL%[+ABS]"),
    (["--noise", "preload_N=0.5"], None, "--noise preload_N=0.5: preload_N is not a measured"),
    ([], [1.0] * 5 + [-1.0] + [1.0] * 6, "line 7, column 'sigma_torque_Nmm': -1: a standard"),
    ([], [1.0] * 3 + ["nan"] + [1.0] * 8, "line 5, column 'sigma_torque_Nmm': value is nan"),
    (["--noise", "torque_Nmm=1%"], [1.0] * 12, "also has sigma_torque_Nmm"),
])
def test_bad_noise_input_is_one_line_and_exit_2(tmp_path, capsys, args, sigma, message):
    """Bad --noise values and sigma_ columns: exit code 2, one line naming the flag or the file
    and line, nothing written."""
    f = _measured_csv(tmp_path, sigma)
    out = tmp_path / "o"
    assert main(["diagnose", str(SEED000), str(f), "--out", str(out), *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err
    assert not out.exists()


# ------------------------------------------------------------------ made another way (slow)
FLYWHEEL = CONFIG_DIR / "seed001_flywheel_hybrid.toml"


def first_order_lag(t: np.ndarray, u: np.ndarray, tau_s: float) -> np.ndarray:
    """A lumped body's temperature behind the input u (Incropera & DeWitt, Fundamentals of Heat
    and Mass Transfer, ch. 5.3: tau dT/dt = u - T), by backward Euler on a 1 s grid from rest
    (not the effect code's exact piecewise-linear response), sampled at t."""
    fine = np.arange(t[0], t[-1] + 0.5, 1.0)
    uf = np.interp(fine, t, u)
    a = 1.0 / (1.0 + 1.0 / tau_s)
    y = signal.lfilter([1.0 - a], [1.0, -a], uf, zi=[a * uf[0]])[0]
    return np.interp(t, fine, y)


@pytest.mark.slow
def test_lag_with_percent_of_reading_noise_is_explained_with_its_tau():
    """The flywheel pair (seed 001) over 200 rows of 120 s, chamber -60..60 C and 2000..9000
    rpm out of phase: its torque spans 33 to 20 000 N mm. Every part follows the chamber
    through a 1500 s first-order lag (`first_order_lag`, this file), the measured file gives
    time, chamber and speed only, the torque carries 1.5 % of reading noise. Stated as
    `--noise torque_Nmm=1.5%`, the lag is explained with its tau's interval holding 1500 s and
    the statement found consistent; without the statement the same data are not explained
    (there: `unexplained`, as on data the issue names, with a fitted tau of 1507 s)."""
    import bearingfem

    meas = _flywheel_lag_with_percent_noise(1)
    stated = bearingfem.diagnose(FLYWHEEL, meas, noise={"torque_Nmm": "1.5%"})
    _assert_lag_explained(stated, "stated")
    assert stated.json["noise_model"]["torque_Nmm"]["rel"] == 0.015
    plain = bearingfem.diagnose(FLYWHEEL, meas)
    assert plain.verdict != "explained", plain.json["reasons"]


def _flywheel_lag_with_percent_noise(seed: int) -> dict:
    """The measured table of the flywheel lag (`test_lag_with_percent_of_reading_noise_...`):
    time, chamber, speed and the torque with 1.5 % of reading noise (draw `seed`)."""
    import bearingfem
    from studies.model.inputs import PART_COLUMNS

    t = np.arange(200) * 120.0
    period = t[-1] / 2
    amb = 60.0 * np.sin(2 * np.pi * t / period)
    speed = 5500.0 + 3500.0 * np.sin(2 * np.pi * t / (0.77 * period) + 1.0)
    parts = first_order_lag(t, amb, 1500.0)
    truth = bearingfem.simulate(FLYWHEEL, {"time_s": t, "T_ambient_C": amb, "speed_rpm": speed,
                                           **{c: parts for c in PART_COLUMNS}})
    tq = truth["torque_Nmm"].to_numpy()
    assert tq.max() / tq.min() > 100.0
    rng = np.random.default_rng(seed)
    return {"time_s": t, "T_ambient_C": amb, "speed_rpm": speed,
            "torque_Nmm": tq * (1.0 + 0.015 * rng.standard_normal(t.size))}


def _assert_lag_explained(r, source: str):
    """Explained by the lag, its tau's 95 % interval holding the 1500 s the data were made
    with, the statement (`source`) found consistent with the data."""
    assert r.verdict == "explained" and r.cause == "thermal_lag", r.json["reasons"]
    tau = r.json["parameters"]["tau_s"]
    u = r.json["parameter_uncertainty"]["tau_s"]               # standard uncertainty, s
    assert abs(tau - 1500.0) <= 1.96 * u, (tau, u)             # its 95 % interval
    nm = r.json["noise_model"]["torque_Nmm"]
    assert nm["source"] == source and nm["consistent"] is True, nm


@pytest.mark.slow
def test_lag_with_a_sigma_column_of_percent_of_reading_is_explained_with_its_tau():
    """The same data with the noise stated per row as a rig's file states it: a
    `sigma_torque_Nmm` column of 1.5 % of each measured value (which carries the reading's own
    noise: `calibration.stated_columns_smoothed`; before its running mean `unexplained`, the
    data's level 13 x the statement). Explained by the lag with its tau's interval holding
    1500 s, the statement consistent."""
    import bearingfem

    meas = _flywheel_lag_with_percent_noise(1)
    meas["sigma_torque_Nmm"] = 0.015 * np.abs(meas["torque_Nmm"])
    _assert_lag_explained(bearingfem.diagnose(FLYWHEEL, meas), "column")


# ------------------------------------------------------------------ item 5: the configured model's interval
def test_configured_interval_covers_ninety_percent_of_a_repeat_run():
    """The configured model's 90 % interval with the discrepancy the data show
    (`interval.configured_intervals`) about a model that misses a smooth curve of 4 noise
    sigma in the conditions (the truth 2 x + 4 sigma sin(T / 25 K): no nuisance value fits it)
    holds 90 % of the entries of fresh repeat runs of the same rows (the truth with new noise;
    100 repeats of the same fit, 120 entries each: binomial standard deviation of the mean 0.3 %,
    the fit's own draw moves it more: 85-95 %), with 1.5 % of reading noise stated; and it is
    not centred on the configured model (the discrepancy is in it)."""
    from studies.diagnosis.interval import configured_intervals

    rng = np.random.default_rng(5)
    n = 120
    T = np.linspace(-40.0, 80.0, n)
    x = 1000.0 * np.exp(T / 40.0)                      # the configured model's reading, 2 decades
    s = 0.015 * 2.0 * x
    level = float(np.sqrt(np.mean(s ** 2)))
    truth = 2.0 * x + 4.0 * level * np.sin(T / 25.0) * s / level
    cond = {"T_ambient_C": T}

    def predict(effects, nuisance):
        return {"torque_Nmm": nuisance["mu_scale"] * x}
    stated = {"torque_Nmm": StatedNoise("stated", rel=0.015)}
    cover = []
    for _ in range(4):                                  # four fits, each with 25 repeat runs
        y = truth + s * rng.standard_normal(n)
        pb, base = calibrate(make_problem(predict, {"torque_Nmm": y}, cond, [], NUISANCE,
                                          noise_model=stated))
        iv = configured_intervals(pb, base.fit)
        lo, hi = iv.columns["torque_Nmm"].lo, iv.columns["torque_Nmm"].hi
        mid = 0.5 * (lo + hi)
        assert np.max(np.abs(mid - base.fit.pred["torque_Nmm"]) / s) > 2.0
        for _ in range(25):
            again = truth + s * rng.standard_normal(n)
            cover.append(np.mean((again >= lo) & (again <= hi)))
    assert 0.85 <= float(np.mean(cover)) <= 0.95, np.mean(cover)


def test_a_drifting_sensor_stated_as_white_gets_its_ar1_model():
    """A stated level is checked on the white (second-difference) level first: a white sensor
    stated right keeps rho = 0; a sensor whose noise is AR(1) with phi 0.9 (marginal level as
    stated) shows a second-difference level 0.26 of it, the statement fails and the AR(1) model
    is fitted (its REML rho above 0.7 on 240 rows), the data's marginal level within 35 % of the
    truth (the AR(1) level of 240 rows at phi 0.9 has about 24 effective entries)."""
    rng = np.random.default_rng(7)
    n = 240
    x = np.geomspace(100.0, 20000.0, n)
    s = 0.015 * 2.0 * x
    cond = {"time_s": np.arange(n) * 120.0, "T_ambient_C": np.linspace(-20.0, 60.0, n)}

    def predict(effects, nuisance):
        return {"torque_Nmm": nuisance["mu_scale"] * x}
    e = np.zeros(n)
    w = rng.standard_normal(n) * np.sqrt(1 - 0.81)
    e[0] = rng.standard_normal()
    for i in range(1, n):
        e[i] = 0.9 * e[i - 1] + w[i]
    stated = {"torque_Nmm": StatedNoise("stated", rel=0.015)}
    for noise, drifting in ((rng.standard_normal(n), False), (e, True)):
        y = 2.0 * x + s * noise
        pb, _ = calibrate(make_problem(predict, {"torque_Nmm": y}, cond, [], NUISANCE,
                                       noise_model=stated))
        rho = pb.noise.rho["torque_Nmm"]
        assert (rho > 0.7) if drifting else (rho == 0.0), (drifting, rho)
        assert pb.noise.sigma["torque_Nmm"] == pytest.approx(
            pb.noise.stated_sigma["torque_Nmm"], rel=0.35 if drifting else 0.15)


def test_a_model_error_at_the_lowest_readings_is_not_taken_for_spikes():
    """Weights of a stated share of reading make a model error at the lowest readings large in
    the standardised residual: on the forced-air history with 1.5 % of reading
    (`thermal_history` th_forced_air_reading_noise, seed 0) the spike test left the 5 rows of
    the hot end's lowest torque (0.13-0.21 N mm) out as spikes, a misfit of the configured
    model there. A model error is a run of rows; a sensor spike is one reading. Here: a torque
    over two decades (1000 exp(T / 25 K), T = 60 C sin over two cycles of 240 rows of 120 s),
    noise 1.5 % of reading, stated so; the model mu x misses a bump of 20 % of the reading over
    the 5 rows about the lowest reading (13 stated sigma; without the run rule all 5 were left
    out) and the file has 3 isolated spikes of 60 stated sigma at rows placed here. The spikes
    left out are exactly those 3 rows (1-based)."""
    rng = np.random.default_rng(11)
    n = 240
    t = np.arange(n) * 120.0
    T = 60.0 * np.sin(2.0 * np.pi * t / (t[-1] / 2.0))
    x = 1000.0 * np.exp(T / 25.0)
    low = int(np.argmin(x))
    bump = np.zeros(n)
    bump[low - 2:low + 3] = 0.20
    spikes = np.array([30, 100, 160])
    assert np.all(np.abs(spikes - low) > 10)
    e = rng.standard_normal(n)
    e[spikes] = 60.0
    y = x * (1.0 + bump) * (1.0 + 0.015 * e)

    def predict(effects, nuisance):
        return {"torque_Nmm": nuisance["mu_scale"] * x}
    pb, _ = calibrate(make_problem(predict, {"torque_Nmm": y}, {"time_s": t, "T_ambient_C": T},
                                   [], NUISANCE,
                                   noise_model={"torque_Nmm": StatedNoise("stated", rel=0.015)}))
    assert sorted(pb.spikes.get("torque_Nmm", [])) == list(spikes + 1), pb.spikes
