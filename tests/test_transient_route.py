"""`simulate` in transient mode (studies/model/transient_route.py): the steady limit without heat
against the given-temperature route, the coupling interval against every step, the `[thermal]`
keys and the transient conditions' bad input (one line, exit 2)."""
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from studies.model.config import ConfigError, Thermal, assembly_from_dict, load_shipped
from studies.model.table import TableError

CONFIG = Path("studies/configs/seed003_25TAC62B.toml")
#: the films of seed 003's study (housing 15, shaft 60 W/m2K; the rest of the stack 30)
FILMS = (("housing_outer", 15.0), ("free_housing", 15.0), ("free_cover", 15.0),
         ("shaft_end", 60.0), ("free_shaft", 60.0), ("free_nut", 60.0), ("*", 30.0))
MESH_FACTOR = 2.0           # a coarse member of the mesh family: the loop, not the discretisation


@pytest.fixture(scope="module")
def pl():
    from studies.model.pipeline import Pipeline

    asm = replace(load_shipped("seed003"), thermal=Thermal(mode="transient", films=FILMS))
    return Pipeline(asm, mesh_factor=MESH_FACTOR)


def test_without_heat_the_long_run_ends_uniform_at_the_ambient_as_the_given_route(pl):
    """At rest (no friction heat) and a step of the ambient from 25 to 45 C, the transient run
    ends, after many time constants, in the uniform field at 45 C (the steady heat equation with
    one fluid temperature and no source: T = T_amb everywhere). Its preload, fit pressures and
    groove shifts then equal those of the given-temperature route (`Pipeline.run`, every part
    at 45 C: per-part unit solutions, not the modal response): to 1e-6 of the change from 25 C."""
    from studies.model.columns import to_columns
    from studies.model.inputs import baseline_inputs
    from studies.model.transient_route import run_transient

    t = np.array([0.0, 1.0, 4e5])
    cols = {"time_s": t, "T_ambient_C": np.array([25.0, 45.0, 45.0]), "speed_rpm": np.zeros(3)}
    r = run_transient(pl, cols, dt_s=2000.0).columns()
    for p in ("shaft", "inner_ring", "ball", "outer_ring", "housing", "spacer"):
        assert abs(r[f"T_{p}_C"][-1] - 45.0) < 1e-6 * 20.0, p
    assert abs(r["T_max_C"][-1] - 45.0) < 1e-6 * 20 and abs(r["T_min_C"][-1] - 45.0) < 1e-6 * 20
    asm = pl.asm
    given = to_columns(pl.run(baseline_inputs({"T_ambient_C": np.array([25.0, 45.0]),
                                               "speed_rpm": np.zeros(2)},
                                              2, asm.T_ref_C, asm.preload.assembled_N, 0.0)))
    for k in ("preload_N", "groove_shift_dr_A_um", "groove_shift_dz_A_um"):
        change = abs(given[k][1] - given[k][0])
        assert change > 0, k
        assert abs(r[k][-1] - given[k][1]) < 1e-6 * change, (k, r[k][-1], given[k][1])
    for k in ("fit_pressure_inner_MPa", "fit_pressure_outer_MPa"):
        assert abs(r[k][-1] - given[k][1]) <= 1e-9 * abs(given[k][1]), (k, r[k][-1], given[k][1])
    assert r["heat_bearing_W"][-1] == 0.0


@pytest.mark.slow        # ~60 s on 2 cores; the coupled loop stays in the default suite through
# test_the_coupled_run_conserves_energy_step_by_step
def test_heat_up_couples_and_the_coupling_interval_is_converged(pl):
    """A 20-minute heat-up at 1500 rpm: the friction heat warms the balls above the rings and
    the rings above the housing (heat flows from the contacts outwards), and the heat falls as
    the preload relaxes from its first peak... The loop refreshed every 5th step (the default)
    agrees with the loop closed at every step to 1 % of the preload's change and 2 % of the
    temperature rise (the coupling lag is 10 s against time constants of minutes)."""
    from studies.model.transient_route import run_transient

    t = np.linspace(0.0, 1200.0, 5)
    cols = {"time_s": t, "T_ambient_C": np.full(5, 25.0), "speed_rpm": np.full(5, 1500.0),
            "preload_assembled_N": np.full(5, 1500.0)}
    every5 = run_transient(pl, cols).columns()
    every1 = run_transient(pl, cols, couple_every=1).columns()
    T = {p: every5[f"T_{p}_C"][-1] for p in ("ball", "inner_ring", "outer_ring", "housing")}
    assert T["ball"] > T["inner_ring"] > T["outer_ring"] > T["housing"] > 25.0
    P1 = every1["preload_N"]
    assert np.max(np.abs(every5["preload_N"] - P1)) < 0.01 * np.ptp(P1)
    rise = every1["T_ball_C"] - 25.0
    assert np.max(np.abs(every5["T_ball_C"] - every1["T_ball_C"])) < 0.02 * rise.max()
    assert np.all(every5["reduction_error_est"] < 1e-3)
    assert np.all(every5["heat_bearing_W"][1:] > 0)


def test_thermal_keys_refuse_bad_values_in_one_line():
    raw = tomllib.loads(CONFIG.read_text())
    raw["thermal"] = {"mode": "transient", "emissivity": 1.5}
    with pytest.raises(ConfigError, match=r"thermal.emissivity: must lie in 0..1, got 1.5"):
        assembly_from_dict(raw, "x.toml")
    raw["thermal"] = {"mode": "transient", "fit_conductance": "gap"}
    with pytest.raises(ConfigError, match="thermal.fit_conductance"):
        assembly_from_dict(raw, "x.toml")
    raw["thermal"] = {"mode": "transient", "films": {"housing_outer": -1.0}}
    with pytest.raises(ConfigError, match="thermal.films: housing_outer: must be a finite number"):
        assembly_from_dict(raw, "x.toml")
    raw["thermal"] = {"mode": "transient", "films": {"housing_outer": 15.0, "raceway_*": 30.0},
                      "fit_conductance": 5000.0, "sink_C": -20.0}
    th = assembly_from_dict(raw, "x.toml").thermal
    assert th.films_W_m2K() == {"housing_outer": 15.0, "raceway_*": 30.0}
    assert th.fit_conductance == 5000.0 and th.sink_C == -20.0


def test_films_resolve_exact_names_before_patterns_and_refuse_unknown_names():
    from studies.model.transient_route import resolve_films

    groups = ["housing_outer", "free_housing", "raceway_inner_ring_A", "raceway_outer_ring_A"]
    got = resolve_films({"*": 30.0, "raceway_*": 50.0, "free_housing": 15.0}, groups)
    assert got == {"housing_outer": 30.0, "free_housing": 15.0, "raceway_inner_ring_A": 50.0,
                   "raceway_outer_ring_A": 50.0}
    with pytest.raises(ConfigError, match="thermal.films.housing_out: matches no face group"):
        resolve_films({"housing_out": 1.0}, groups)


def test_transient_conditions_refuse_given_part_temperatures_and_need_time():
    from studies.model.transient_route import environment

    asm = replace(load_shipped("seed003"), thermal=Thermal(mode="transient", films=FILMS))
    with pytest.raises(TableError, match="column 'time_s': required in transient mode"):
        environment(asm, {"T_ambient_C": np.zeros(2)})
    with pytest.raises(TableError, match="column 'T_shaft_C': part temperatures are computed"):
        environment(asm, {"time_s": np.arange(2.0), "T_ambient_C": np.zeros(2),
                          "T_shaft_C": np.zeros(2)})
    with pytest.raises(TableError, match="needs the column T_ambient_C or T_sink_C"):
        environment(asm, {"time_s": np.arange(2.0)})
    with pytest.raises(TableError, match="row 2, column 'film_scale': -1 below 0"):
        environment(asm, {"time_s": np.arange(2.0), "T_sink_C": np.zeros(2),
                          "film_scale": np.array([1.0, -1.0])})
    env = environment(asm, {"time_s": np.arange(2.0), "T_sink_C": np.array([-20.0, -30.0])})
    assert np.array_equal(env.T_ambient_C, [-20.0, -30.0]) and np.array_equal(env.heat_W, [0, 0])


def test_simulate_command_refuses_a_part_temperature_in_transient_mode(tmp_path, capsys):
    """Through the command's entry point in this process (its return value is the exit code; the
    real process's exit codes: tests/test_guard_rails.py)."""
    from studies.app.cli import main

    cfg = tmp_path / "t.toml"
    cfg.write_text(CONFIG.read_text() + '\n[thermal]\nmode = "transient"\n')
    cond = tmp_path / "c.csv"
    cond.write_text("time_s,T_ambient_C,T_shaft_C\n0,25,25\n10,25,26\n")
    out = tmp_path / "o.csv"
    code = main(["simulate", str(cfg), str(cond), "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.strip().count("\n") == 0 and "T_shaft_C" in err
    assert not out.exists()


def test_the_reduced_basis_is_cached_and_a_damaged_entry_rebuilt(pl, capsys):
    """A second pipeline of the same stack reads the basis from the cache (the same modes to the
    bit); a damaged file is removed with one warning and rebuilt (meshes/cache.py's rules)."""
    from meshes.cache import cache_dir
    from studies.model.pipeline import Pipeline
    from studies.model.transient_route import thermal_model

    V1 = thermal_model(pl).rc.V
    files = list(cache_dir("setups").glob("thermal_*.npz"))
    assert files
    again = thermal_model(Pipeline(pl.asm, mesh_factor=MESH_FACTOR)).rc.V
    assert np.array_equal(again, V1)
    for f in files:
        f.write_bytes(b"not an npz")
    capsys.readouterr()
    rebuilt = thermal_model(Pipeline(pl.asm, mesh_factor=MESH_FACTOR)).rc.V
    assert "reduced thermal basis" in capsys.readouterr().err
    assert np.allclose(rebuilt, V1, rtol=0, atol=1e-9 * np.abs(V1).max())


def test_simulate_file_in_transient_mode_writes_the_transient_columns(pl, tmp_path):
    """`simulate`'s file route in transient mode (`simulate_transient_file`; the chunked
    `stream.simulate_file` refuses a transient assembly): the condition columns, the computed part
    temperatures and the transient columns of docs/cli.md, the numbers those of
    `run_transient` (one route), flags and margins as in given mode."""
    import pandas as pd

    from studies.model.stream import simulate_file
    from studies.model.transient_route import run_transient, simulate_transient_file

    cond = tmp_path / "c.csv"
    cond.write_text("time_s,T_ambient_C,speed_rpm,heat_W\n0,25,1000,0\n300,25,1000,2\n600,30,1000,2\n")
    out = tmp_path / "o.csv"
    with pytest.raises(ValueError, match="simulate_transient_file"):
        simulate_file(pl.asm, cond, out, pipeline=pl)
    run = simulate_transient_file(pl.asm, cond, out, pipeline=pl)
    assert run.n_rows == 3
    got = pd.read_csv(out)
    for c in ("time_s", "T_ambient_C", "heat_W", "T_shaft_C", "T_inner_ring_C", "T_ball_C",
              "T_outer_ring_C", "T_housing_C", "T_spacer_C", "T_max_C", "T_min_C",
              "heat_bearing_W", "reduction_error_est", "preload_N", "torque_Nmm"):
        assert c in got.columns, c
    assert any(c.startswith("flag_") for c in got.columns)
    ref = run_transient(pl, {"time_s": np.array([0.0, 300, 600]), "T_ambient_C": np.array([25.0, 25, 30]),
                             "speed_rpm": np.full(3, 1000.0), "heat_W": np.array([0.0, 2, 2])}).columns()
    for c in ("preload_N", "T_ball_C", "heat_bearing_W"):
        assert np.allclose(got[c], ref[c], rtol=1e-9, atol=0), c     # written with 10 digits
    assert np.all(got["heat_bearing_W"][1:] > 2.0)
    # the conditions' heat_W is written as given (the route's torque power, also
    # named heat_W, overwrote it: 46.99 W where the file said 2)
    assert np.array_equal(got["heat_W"], [0.0, 2.0, 2.0])


def test_bench_transient_flag_runs_the_transient_bench(monkeypatch):
    import studies.bench.bench_transient as bt
    from studies.app.cli import main

    calls = []
    monkeypatch.setattr(bt, "main", lambda argv: calls.append(argv))
    assert main(["bench", "--transient"]) in (0, None)
    assert calls == [[]]


def test_the_transient_bench_runs_its_route_and_the_reduction_agrees_with_the_full_fe():
    """`bench --transient` on a few steps: its reduced heat-up against its full-FE one (the
    bound: 1e-3 of the preload) and the a-posteriori estimate above the error (it broke
    unnoticed when the pipeline became stages: the flag test above replaces the bench)."""
    import studies.bench.bench_transient as bt

    r = bt.run(n_steps=12, update_every=6)
    assert r.compared_steps > 0 and r.preload_err < 1e-3
    assert r.preload_err <= r.preload_est


def test_the_coupled_run_conserves_energy_step_by_step(pl):
    """Energy balance of every step of a coupled heat-up with extra heat and a film factor that
    changes: heat in (the pair's friction heat at the coupling state + heat_W, as the run
    reports it) = stored (capacity x the scheme's dT/dt: backward Euler first, then BDF2) +
    convected (sum_g h_g int (T - T_amb) dA), to 1e-9 of the largest term. The uniform field is
    a mode of the reduction, so the projected equations keep this law exactly (Galerkin with
    the test function 1); it checks that every watt the loop computes reaches the FE once."""
    from fem.transient import PER_M2_TO_PER_MM2, SCHEMES
    from studies.model.transient_route import run_transient, thermal_model

    t = np.array([0.0, 200.0, 400.0])
    cols = {"time_s": t, "T_ambient_C": np.array([25.0, 25.0, 28.0]),
            "speed_rpm": np.full(3, 1500.0), "heat_W": np.array([0.0, 5.0, 5.0]),
            "film_scale": np.array([1.0, 1.0, 2.0])}
    r = run_transient(pl, cols)
    tm = thermal_model(pl)
    tc = tm.tc
    T = r.q @ tm.rc.V.T
    dt = r.grid_s[1] - r.grid_s[0]
    amb = np.interp(r.grid_s, t, cols["T_ambient_C"])
    scale = np.interp(r.grid_s, t, cols["film_scale"])
    E = T @ (tc.M @ np.ones(tc.n_total))               # J, the stored energy of each state
    worst = 0.0
    for k in range(1, r.grid_s.size):
        c0, c1, c2 = SCHEMES["backward_euler" if k == 1 else "bdf2"]
        stored = (c0 * E[k] - c1 * E[k - 1] - (c2 * E[k - 2] if k > 1 else 0.0)) / dt
        conv = sum(scale[k] * h * PER_M2_TO_PER_MM2 * (tc.b[g] @ T[k] - tc.b[g].sum() * amb[k])
                   for g, h in tm.nominal.film_W_m2K.items())
        terms = (r.heat_W[k], stored, conv)
        worst = max(worst, abs(r.heat_W[k] - stored - conv) / max(abs(x) for x in terms))
    assert worst < 1e-9, worst
    assert r.heat_W[-1] > 5.0


def test_in_vacuum_the_stack_radiates_to_the_sink_of_the_thermal_section():
    """No films, emissivity 0.8 on the exterior, `[thermal] sink_C = -20` and only T_ambient_C
    in the conditions (which then drives nothing): at rest the stack cools from 25 C by
    radiation alone and ends uniform at the sink (steady radiation without a source: T_K^4 =
    T_sink,K^4; Incropera ch. 12), to 1e-6 of the 45 K drop, cooling all the way."""
    from studies.model.pipeline import Pipeline
    from studies.model.transient_route import run_transient

    asm = replace(load_shipped("seed003"),
                  thermal=Thermal(mode="transient", emissivity=0.8, sink_C=-20.0))
    pl = Pipeline(asm, mesh_factor=MESH_FACTOR)
    t = np.array([0.0, 3600.0, 10 * 3600.0, 1.5e6])
    r = run_transient(pl, {"time_s": t, "T_ambient_C": np.full(4, 25.0), "speed_rpm": np.zeros(4)},
                      dt_s=3000.0).columns()
    assert abs(r["T_max_C"][-1] + 20.0) < 1e-6 * 45 and abs(r["T_min_C"][-1] + 20.0) < 1e-6 * 45
    assert 25.0 > r["T_housing_C"][1] > r["T_housing_C"][2] > -20.0


@pytest.mark.slow        # ~30 s; the second source's transient case: tests/test_second_source.py
def test_part_temperatures_for_the_second_source_are_simulates_columns(pl):
    """`part_temperatures` (the diagnosis's second source of lagged temperatures) gives the part
    temperatures `simulate` in transient mode writes (the same route, bit for bit), starts at
    the first environment temperature and, at rest, stays between the environment's extremes
    (maximum principle: no source), lagging it: after a step up every part is still below it."""
    from studies.model.transient_route import part_temperatures, run_transient

    t = np.array([0.0, 60.0, 600.0, 1800.0])
    amb = np.array([20.0, 40.0, 40.0, 40.0])
    pt = part_temperatures(pl.asm, t, amb, np.zeros(4), pipeline=pl)
    cols = run_transient(pl, {"time_s": t, "T_ambient_C": amb, "speed_rpm": np.zeros(4)}).columns()
    for p in pt.parts:
        assert np.array_equal(pt.of(p), cols[f"T_{p}_C"]), p
    assert "ball" in pt.parts and "spacer" in pt.parts
    assert np.allclose(pt.T_C[0], 20.0, atol=1e-9)
    assert np.all(pt.T_C >= 20.0 - 1e-9) and np.all(pt.T_C[1:] < 40.0)
    assert np.all(np.diff(pt.T_C, axis=0) >= -1e-9)      # heating only


def test_a_stack_with_no_films_heats_as_a_field_and_stores_every_watt(pl):
    """`[thermal] mode = "transient"` without `[thermal.films]` (adiabatic outside).
    Before, every part had one temperature in every row (the reduced basis was the uniform field
    alone: T_max_C == T_min_C to all digits) although the heat enters at the raceways. Now: the
    raceways' parts run warmer than the housing, and every watt is stored (no film: heat in =
    capacity x the scheme's dT/dt, step by step, to 1e-9 of the heat: a lumped adiabatic body's
    balance); a warning line says the stack is adiabatic."""
    from fem.transient import SCHEMES
    from studies.model.checks import plausibility_warnings
    from studies.model.pipeline import Pipeline
    from studies.model.transient_route import run_transient, thermal_model

    asm = replace(pl.asm, thermal=Thermal(mode="transient"))
    assert any("adiabatic" in w for w in plausibility_warnings(asm))
    bare = Pipeline(asm, mesh_factor=MESH_FACTOR)
    t = np.array([0.0, 300.0, 600.0])
    cols = {"time_s": t, "T_ambient_C": np.array([-40.0, -30.0, -20.0]),
            "speed_rpm": np.full(3, 1500.0), "heat_W": np.full(3, 2.0)}
    r = run_transient(bare, cols)
    rows = r.columns()
    assert np.all(rows["T_max_C"][1:] - rows["T_min_C"][1:] > 0.1)
    assert np.all(rows["T_inner_ring_C"][1:] > rows["T_housing_C"][1:])
    tc = thermal_model(bare).tc
    E = (r.q @ thermal_model(bare).rc.V.T) @ (tc.M @ np.ones(tc.n_total))      # J
    dt = r.grid_s[1] - r.grid_s[0]
    worst = 0.0
    for k in range(1, r.grid_s.size):
        c0, c1, c2 = SCHEMES["backward_euler" if k == 1 else "bdf2"]
        stored = (c0 * E[k] - c1 * E[k - 1] - (c2 * E[k - 2] if k > 1 else 0.0)) / dt
        worst = max(worst, abs(r.heat_W[k] - stored) / r.heat_W[k])
    assert worst < 1e-9, worst
