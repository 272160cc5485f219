"""Every study reaches the model through the pipeline: its tables equal `simulate` on the same
rows (the command-line route: conditions table -> baseline inputs -> pipeline), and it writes its
report, plots and field images. Studies run on a coarser mesh here (mesh_factor 4); the three
studies take about 40 s, so the module is in `make test-slow`,
as are the runs at the shipped mesh (test_cli_studies.py)."""
import csv
import functools

import numpy as np
import pytest

from studies.model.pipeline import simulate_table
from studies.model.config import load_shipped
from studies.model.pipeline import Pipeline
from studies.validation import study_module
from studies.model.columns import to_columns

pytestmark = pytest.mark.slow

MESH_FACTOR = 4.0
#: relative to the value compared: both routes do the same arithmetic, and the study's CSV keeps 10
#: significant digits (at most 5e-10 relative)
RTOL = 1e-9


def _read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(r for r in f if not r.startswith("#")))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


@pytest.fixture(scope="module")
def studies(tmp_path_factory):
    out = {}
    # seed000's field images at one temperature and without the 64-stack inverse search (the
    # field-image code is the same at each; all of it at the shipped mesh in the slow study run,
    # the search's recovery of a planted trend in test_design.py)
    more = {"seed000": {"field_temperatures_C": (-60.0,), "inverse_search": False}}
    for name in ("seed000", "seed001", "seed003"):
        d = tmp_path_factory.mktemp(name)
        study_module(name).run(d, progress=lambda s: None, mesh_factor=MESH_FACTOR,
                               **more.get(name, {}))
        out[name] = d
    return out


@functools.lru_cache(maxsize=None)
def _pipeline(name):
    """simulate's pipeline of a shipped assembly at the studies' mesh, built once per assembly
    (a Pipeline keeps no state between runs but its FE cache keyed by exact inputs)."""
    return Pipeline(load_shipped(name), mesh_factor=MESH_FACTOR)


def _simulate(name, columns):
    pl = _pipeline(name)
    return to_columns(simulate_table(pl.asm, columns, pipeline=pl))


def _close(a, b, what):
    np.testing.assert_allclose(a, b, rtol=RTOL, atol=RTOL * np.max(np.abs(b)), err_msg=what)


def test_seed000_tables_equal_simulate(studies):
    d = studies["seed000"]
    sweep = _read(d / "temperature_sweep.csv")
    sim = _simulate("seed000", {"T_ambient_C": sweep["T_C"]})
    for k in ("preload_N", "torque_Nmm", "contact_angle_deg", "fit_pressure_inner_MPa",
              "max_contact_pressure_MPa"):
        _close(sweep[k], sim[k], f"temperature_sweep {k}")
    # the preload decomposition's total is the same model (it once left the compliance out)
    _close(_read(d / "preload_decomposition.csv")["preload_N"], sim["preload_N"], "decomposition")
    cyc = _read(d / "cycles.csv")
    sim = _simulate("seed000", {"T_ambient_C": cyc["T_C"], "time_s": 3600 * cyc["time_h"]})
    _close(cyc["preload_baseline_N"], sim["preload_N"], "cycles preload")
    _close(cyc["torque_baseline_Nmm"], sim["torque_Nmm"], "cycles torque")
    tq = _read(d / "torque_vs_preload.csv")
    sim = _simulate("seed000", {"preload_assembled_N": tq["preload_assembled_N"]})
    _close(tq["torque_Nmm"], sim["torque_Nmm"], "torque vs preload")
    # the assembly report the study is built on: its results table is simulate's too
    res = _read(d / "results.csv")
    sim = _simulate("seed000", {"T_ambient_C": res["T_ambient_C"]})
    for k in ("preload_N", "torque_Nmm", "fit_pressure_outer_MPa"):
        _close(res[k], sim[k], f"report results {k}")
    report = (d / "report.md").read_text()
    assert "| quantity |" in report and "published measurement" in report
    for f in ("fits.png", "preload_vs_temperature.png", "cycles.png",
              "field_-60C_von_mises_MPa.png", "field_-60C.vtu"):
        assert (d / f).stat().st_size > 1000, f


def test_seed001_tables_equal_simulate(studies):
    d = studies["seed001"]
    for n in (3500, 9000):
        t = _read(d / f"torque_vs_temperature_{n}rpm.csv")
        sim = _simulate("seed001", {"T_ambient_C": t["T_C"], "speed_rpm": np.full(t["T_C"].size, n)})
        for k in ("preload_N", "torque_Nmm", "contact_angle_deg"):
            _close(t[k], sim[k], f"{n} rpm {k}")
    # the ratio map's configured row (FE compliance, configured f0) is simulate's model
    rm = _read(d / "ratio_map.csv")
    asm = load_shipped("seed001")
    sim = _simulate("seed001", {"T_ambient_C": np.array([-20.0, 20.0, 60.0]),
                                "speed_rpm": np.full(3, asm.lubrication.speed_rpm)})
    n_f0 = int(np.sum(rm["compliance_mm_per_N"] == 0.0))     # rows of the first (rigid) compliance
    row = n_f0 * 1                                     # compliance index 1 (FE), f0 index 0
    assert rm["f0"][row] == asm.lubrication.viscous_factor_f0
    _close(rm["ratio_cold"][row], sim["torque_Nmm"][0] / sim["torque_Nmm"][1], "ratio cold")
    _close(rm["ratio_hot"][row], sim["torque_Nmm"][2] / sim["torque_Nmm"][1], "ratio hot")
    assert (d / "ratio_map.png").stat().st_size > 1000


def test_seed003_tables_equal_simulate(studies):
    d = studies["seed003"]
    for n in (1000, 1500):
        h = _read(d / f"heat_up_{n}rpm.csv")
        cols = {f"T_{p}_C": h[f"T_{p}_C"] for p in ("shaft", "inner_ring", "ball", "outer_ring",
                                                     "housing")}
        cols["T_spacer_C"] = 0.5 * (h["T_inner_ring_C"] + h["T_outer_ring_C"])
        cols["speed_rpm"] = np.full(h["time_s"].size, float(n))
        sim = _simulate("seed003", cols)
        _close(h["preload_N"], sim["preload_N"], f"{n} rpm preload")
        _close(h["contact_angle_deg"], sim["contact_angle_deg"], f"{n} rpm contact angle")
    assert (d / "heat_split_1500rpm.png").stat().st_size > 1000
