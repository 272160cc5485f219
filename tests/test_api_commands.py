"""Every command's Python twin (`bearingfem.diagnose`, `tolerance`, `design`, `stiffness`,
`report`, `verify`, `bearing`; docs/cli.md "Python API"): the same numbers as the
command on the same inputs, the inputs given in memory (a dict of arrays or a DataFrame) where the
command reads a CSV, `.to_frame()` equal to the CSV the command writes, and bad input raising a
ValueError subclass whose message is the one line the command prints (exit 2).

The command and its function are one route (studies/usecases/api.py), so the check here is that
the in-memory tables, the defaults and the typed results carry the same inputs and numbers as the
files and flags; the physics of each command is tested in its own module.  Runs on the template
assembly on its coarsest mesh (target error 1 %, as tests/test_report_pdf.py) with small tables.
"""
import json

import numpy as np
import pandas as pd
import pytest

import bearingfem
from studies.app.cli import main
from studies.model.config import CONFIG_DIR

TEMPLATE = CONFIG_DIR / "template.toml"
#: the template on the coarsest mesh the sizing rule allows (target 1 %), with fit classes (the
#: tolerance command needs them): a cheap assembly
COARSE = (TEMPLATE.read_text().replace("target_error = 0.001 ", "target_error = 0.01  ")
          .replace('inner_shaft_class = ""  ', 'inner_shaft_class = "k5"')
          .replace('outer_housing_class = ""  ', 'outer_housing_class = "J6"'))
#: the CSV keeps 10 significant digits: a number read back agrees to 5e-10 relative
CSV_RTOL = 1e-9


@pytest.fixture(scope="module")
def asm_path(tmp_path_factory):
    p = tmp_path_factory.mktemp("asm") / "pair.toml"
    p.write_text(COARSE)
    return p


def _csv(path) -> pd.DataFrame:
    return pd.read_csv(path, comment="#")


def _same_frame(api: pd.DataFrame, cli: pd.DataFrame, rtol=CSV_RTOL):
    """Same columns in the same order, numbers equal to the CSV's digits."""
    assert list(api.columns) == list(cli.columns)
    for c in cli.columns:
        if pd.api.types.is_numeric_dtype(cli[c]):
            np.testing.assert_allclose(api[c].to_numpy(float), cli[c].to_numpy(float),
                                       rtol=rtol, atol=1e-300, err_msg=c)
        else:
            assert list(api[c]) == list(cli[c]), c


def _without(doc: dict, *keys) -> dict:
    return {k: v for k, v in doc.items() if k not in keys}


def test_stiffness_twin(tmp_path, asm_path):
    cond = {"T_ambient_C": [-20.0, 20.0, 60.0], "speed_rpm": [0.0, 3000.0, 6000.0]}
    f = tmp_path / "c.csv"
    pd.DataFrame(cond).to_csv(f, index=False)
    out, ross = tmp_path / "k.csv", tmp_path / "r.csv"
    assert main(["stiffness", str(asm_path), str(f), "-o", str(out), "--ross", str(ross)]) == 0
    res = bearingfem.stiffness(asm_path, pd.DataFrame(cond), ross=True)
    _same_frame(res.to_frame(), _csv(out))
    _same_frame(res.ross.to_frame(), _csv(ross))
    # written by the function: the same bytes as the command (provenance included)
    res2 = bearingfem.stiffness(asm_path, f, out=tmp_path / "k2.csv", ross=tmp_path / "r2.csv")
    assert (tmp_path / "k2.csv").read_bytes() == out.read_bytes()
    assert (tmp_path / "r2.csv").read_bytes() == ross.read_bytes() and res2.n_rows == 3


BEARING = """
[bearing]
designation = "6205 test"
bore_mm = 25.0
outside_diameter_mm = 52.0
width_mm = 15.0
ball_diameter_mm = 7.938
ball_count = 9
pitch_diameter_mm = 38.5
inner_groove_ratio = 0.52
outer_groove_ratio = 0.53
radial_internal_clearance_um = 15.0
inner_ring_outer_diameter_mm = 31.0
outer_ring_inner_diameter_mm = 46.0
ring_material = "GCr15"
ball_material = "GCr15"
"""


def test_bearing_twin(tmp_path):
    b = tmp_path / "b.toml"
    b.write_text(BEARING)
    loads = {"radial_load_N": [500.0, 1000.0], "axial_load_N": [200.0, 300.0],
             "speed_rpm": [0.0, 6000.0]}
    f = tmp_path / "l.csv"
    pd.DataFrame(loads).to_csv(f, index=False)
    out = tmp_path / "o.csv"
    assert main(["bearing", str(b), str(f), "-o", str(out), "--control", "jones"]) == 0
    res = bearingfem.bearing(b, loads, control="jones")
    _same_frame(res.to_frame(), _csv(out))
    assert res.n_rows == 2 and res.state.radial_mm.shape == (2,)


@pytest.mark.slow
def test_report_twin(tmp_path, asm_path):
    cond = {"T_ambient_C": [-20.0, 20.0, 60.0]}
    f = tmp_path / "c.csv"
    pd.DataFrame(cond).to_csv(f, index=False)
    assert main(["report", str(asm_path), str(f), "--out", str(tmp_path / "r")]) == 0
    res = bearingfem.report(asm_path, cond)             # no out: a temporary folder
    _same_frame(res.to_frame(), _csv(tmp_path / "r" / "results.csv"))
    assert isinstance(res.warnings, list)


@pytest.mark.slow      # ~8 s, two-thirds of it the report's 12 figures; the call itself is
# test_command_and_function_make_the_same_call[tolerance], the command's numbers tests/test_tolerances.py
def test_tolerance_twin(tmp_path, asm_path):
    f = tmp_path / "c.csv"
    f.write_text("T_ambient_C\n20\n60\n")
    assert main(["tolerance", str(asm_path), str(f), "--samples", "8", "--seed", "3",
                 "--out", str(tmp_path / "t")]) == 0
    res = bearingfem.tolerance(asm_path, {"T_ambient_C": np.array([20.0, 60.0])}, samples=8,
                               seed=3, out=tmp_path / "t2")
    cli = json.loads((tmp_path / "t" / "tolerance.json").read_text())
    assert _without(res.json, "provenance") == _without(cli, "provenance")
    assert (json.loads((tmp_path / "t2" / "tolerance.json").read_text())["probabilities"]
            == cli["probabilities"])
    assert res.preload_lost == cli["probabilities"]["preload_lost"]
    _same_frame(res.to_frame(), _csv(tmp_path / "t" / "samples.csv"))


@pytest.mark.slow
def test_design_twin(tmp_path, asm_path):
    args = ["--range", "0:40", "--band", "0.7:1.3"]
    assert main(["design", str(asm_path), *args, "--out", str(tmp_path / "d")]) == 0
    res = bearingfem.design(asm_path, (0.0, 40.0), band=(0.7, 1.3))
    cli = json.loads((tmp_path / "d" / "design.json").read_text())
    assert _without(res.to_json(), "provenance") == _without(cli, "provenance")
    assert len(res.to_frame()) == len(cli["designs"])


@pytest.mark.slow
def test_verify_twin(tmp_path, asm_path, monkeypatch):
    import functools

    from studies.usecases import verify

    # the manufactured solutions on the coarse levels of tests/test_verify.py (their orders are
    # asserted in tests/test_mms.py; here only the twin's equality)
    monkeypatch.setattr(verify, "mms_cases", functools.partial(verify.mms_cases, (4, 8, 16)))
    monkeypatch.setattr(verify, "transient_mms_cases", lambda: [])
    assert main(["verify", "--out", str(tmp_path / "v"), "--assembly", str(asm_path)]) == 0
    res = bearingfem.verify(assembly=asm_path)
    cli = json.loads((tmp_path / "v" / "verification.json").read_text())
    assert json.loads(json.dumps([c.to_json() for c in res.cases] + [c.to_json() for c in res.convergence],
                                 default=float)) == cli["cases"]
    assert [m.observed_order for m in res.mms] == [m["observed_order"] for m in cli["mms"]]


@pytest.mark.slow
def test_diagnose_twin(tmp_path, asm_path):
    """Ten rows of the model's own output with a small deterministic wobble (no effect hidden):
    the command and the function reach the same verdict and numbers."""
    T = np.linspace(-20.0, 60.0, 10)
    sim = bearingfem.simulate(asm_path, {"T_ambient_C": T})
    wobble = 1.0 + 0.002 * np.sin(np.arange(T.size))
    meas = pd.DataFrame({"T_ambient_C": T, "torque_Nmm": sim["torque_Nmm"] * wobble,
                         "preload_N": sim["preload_N"] * wobble[::-1]})
    f = tmp_path / "m.csv"
    meas.to_csv(f, index=False)
    assert main(["diagnose", str(asm_path), str(f), "--out", str(tmp_path / "d")]) == 0
    res = bearingfem.diagnose(asm_path, meas)
    cli = json.loads((tmp_path / "d" / "diagnosis.json").read_text())
    skip = ("provenance", "seconds", "seconds_by_phase")        # wall-clock times
    assert res.verdict == cli["verdict"] and res.cause == cli.get("cause")
    assert json.loads(json.dumps(_without(res.json, *skip))) == _without(cli, *skip)


class _Stop(Exception):
    """Raised by a recorder in place of a command's work."""


def _record(monkeypatch, module, name):
    """Replace module.name by a recorder of its arguments that stops the run."""
    calls = []

    def fake(*args, **kwargs):
        calls.append((args, kwargs))
        raise _Stop

    monkeypatch.setattr(module, name, fake)
    return calls


def _same_call(monkeypatch, module, name, argv, call, command) -> dict:
    """Run the command line `argv` and the function `call`, each stopped where it calls
    `module.name` (the one function that does the work), and hold the two calls' arguments
    equal; the output folder, the one positional Path (a temporary folder beside --out, or the
    function's own), aside. Returns the function's keyword arguments."""
    calls = _record(monkeypatch, module, name)
    with pytest.raises(_Stop):
        main([str(a) for a in argv])
    with pytest.raises(_Stop):
        call()
    (cli_args, cli_kw), (api_args, api_kw) = calls

    def strip(args):
        return [a for a in args if not hasattr(a, "is_dir")]

    _equal_arguments(strip(cli_args), strip(api_args), command)
    _equal_arguments(cli_kw, api_kw, command)
    return api_kw


def _equal_arguments(a, b, where="") -> None:
    """The arguments a command and its function hand to the shared work are equal: assemblies,
    tables (arrays to the last bit), numbers and flags; not the output folder (a temporary one
    each), the progress callbacks or the provenance (file paths and hashes against an in-memory
    table's)."""
    if isinstance(a, dict) and isinstance(b, dict):
        if {"command", "version", "inputs"} <= set(a):      # a provenance given by position
            assert a["command"] == b["command"] and a["version"] == b["version"], where
            return
        # `_line`: a file's line numbers (named in errors; the work drops `_` columns)
        skip = lambda k: k in ("provenance", "progress", "bar", "command") or k.startswith("_")  # noqa: E731
        keys = [k for k in a if not skip(k)]
        assert keys == [k for k in b if not skip(k)], where
        for k in keys:
            _equal_arguments(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            _equal_arguments(x, y, f"{where}[{i}]")
    elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        assert np.array_equal(np.asarray(a), np.asarray(b)), where
    elif callable(a):
        pass
    else:
        assert a == b, where


@pytest.mark.parametrize("command", ["report", "tolerance", "design", "diagnose", "verify"])
def test_command_and_function_make_the_same_call(tmp_path, asm_path, monkeypatch, command):
    """The fast twin check of the folder-writing commands (the full runs are the slow tests
    above): the command (files, flags) and the function (tables in memory, arguments) hand
    equal assemblies, tables and settings to the one function that does the work."""
    import studies.diagnosis.files as diag_files
    from studies.usecases import assembly_report, design_search, tolerance_report, verify

    T = [-20.0, 20.0, 60.0, 0.0, 10.0, 30.0, 40.0, 50.0]
    meas = pd.DataFrame({"T_ambient_C": T, "torque_Nmm": np.linspace(5.0, 6.0, len(T))})
    f = tmp_path / "t.csv"
    (meas if command == "diagnose" else meas[["T_ambient_C"]]).to_csv(f, index=False)
    module, name, argv, call = {
        "report": (assembly_report, "run", ["report", asm_path, f, "--out", tmp_path / "o"],
                   lambda: bearingfem.report(asm_path, {"T_ambient_C": T})),
        "tolerance": (tolerance_report, "run",
                      ["tolerance", asm_path, f, "--samples", "9", "--seed", "4", "--out",
                       tmp_path / "o"],
                      lambda: bearingfem.tolerance(asm_path, {"T_ambient_C": T}, samples=9, seed=4)),
        "design": (design_search, "run",
                   ["design", asm_path, "--range", "-10:50", "--band-N", "50:300", "--clamps",
                    "--vary", "contact_angle_free_deg=15,25", "--out", tmp_path / "o"],
                   lambda: bearingfem.design(asm_path, (-10, 50), band_N=(50, 300), clamps=True,
                                             vary={"contact_angle_free_deg": (15, 25)})),
        "diagnose": (diag_files, "diagnose_tables", ["diagnose", asm_path, f, "--out", tmp_path / "o"],
                     lambda: bearingfem.diagnose(asm_path, meas)),
        "verify": (verify, "run", ["verify", "--out", tmp_path / "o", "--assembly", asm_path],
                   lambda: bearingfem.verify(assembly=asm_path)),
    }[command]
    _same_call(monkeypatch, module, name, argv, call, command)
    assert not (tmp_path / "o").exists()                 # stopped: nothing left behind


@pytest.mark.parametrize("call,argv,fragment", [
    (lambda p, t: bearingfem.stiffness(p, {"T_ambient_C": [20.0, 400.0]}),
     lambda p, t: ["stiffness", p, t("T_ambient_C\n20\n400\n"), "-o", "x.csv"],
     "row 2, column 'T_ambient_C': 400 outside"),
    (lambda p, t: bearingfem.report(p, {"T_ambient_C": [20.0], "bogus": [1.0]}),
     lambda p, t: ["report", p, t("T_ambient_C,bogus\n20,1\n"), "--out", "r"],
     "column 'bogus': unknown column"),
    (lambda p, t: bearingfem.tolerance(p, {"T_ambient_C": [20.0, float("nan")]}, samples=4),
     lambda p, t: ["tolerance", p, t("T_ambient_C\n20\nnan\n"), "--samples", "4", "--out", "t"],
     "column 'T_ambient_C': value is nan"),
    (lambda p, t: bearingfem.diagnose(p, {"T_ambient_C": [20.0] * 3, "torque_Nmm": [1.0] * 3}),
     lambda p, t: ["diagnose", p, t("T_ambient_C,torque_Nmm\n20,1\n20,1\n20,1\n"), "--out", "d"],
     "3 rows: too few to diagnose"),
])
def test_bad_input_is_the_commands_one_line(tmp_path, asm_path, capsys, monkeypatch, call, argv,
                                            fragment):
    """The function raises a ValueError with the line the command prints (the command names the
    file's line, the function the table's row: both the 1-based data row here, the header being
    line 1 so the file's "line 3" is the table's "row 2")."""
    monkeypatch.chdir(tmp_path)

    def table(text):
        (tmp_path / "in.csv").write_text(text)
        return "in.csv"

    with pytest.raises(ValueError) as exc:
        call(asm_path, table)
    assert fragment in str(exc.value) and "\n" not in str(exc.value)
    assert main([str(a) for a in argv(asm_path, table)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    cli_fragment = fragment.replace("row 2", "line 3")
    assert cli_fragment in err[0], err[0]
    assert not any(p.name in ("x.csv", "r", "t", "d") for p in tmp_path.iterdir())


@pytest.mark.parametrize("command", ["report", "tolerance", "design", "diagnose", "verify"])
def test_with_defaults_the_command_and_function_make_the_same_call(tmp_path, asm_path,
                                                                    monkeypatch, command):
    """Each folder-writing twin with its defaults against its command with its defaults: the
    same settings reach the one function that does the work (the Monte Carlo's samples and
    seed, the design's band, the report's options), so the same numbers come out. The defaults
    are those docs/cli.md states (tolerance: 2000 samples, seed 1; design: band 0.8:1.2)."""
    import studies.diagnosis.files as diag_files
    from studies.usecases import assembly_report, design_search, tolerance_report, verify

    T = [-20.0, 20.0, 60.0, 0.0, 10.0, 30.0, 40.0, 50.0]
    meas = pd.DataFrame({"T_ambient_C": T, "torque_Nmm": np.linspace(5.0, 6.0, len(T))})
    f = tmp_path / "m.csv"
    meas.to_csv(f, index=False)
    module, name, argv, call = {
        "report": (assembly_report, "run", ["report", asm_path, "--out", tmp_path / "o"],
                   lambda: bearingfem.report(asm_path)),
        "tolerance": (tolerance_report, "run", ["tolerance", asm_path, "--out", tmp_path / "o"],
                      lambda: bearingfem.tolerance(asm_path)),
        "design": (design_search, "run", ["design", asm_path, "--range", "-10:50", "--out",
                                          tmp_path / "o"],
                   lambda: bearingfem.design(asm_path, (-10, 50))),
        "diagnose": (diag_files, "diagnose_tables", ["diagnose", asm_path, f, "--out", tmp_path / "o"],
                     lambda: bearingfem.diagnose(asm_path, f)),
        "verify": (verify, "run", ["verify", "--out", tmp_path / "o"], lambda: bearingfem.verify()),
    }[command]
    api_kw = _same_call(monkeypatch, module, name, argv, call, command)
    if command == "tolerance":
        assert (api_kw["samples"], api_kw["seed"]) == (2000, 1)
    if command == "design":
        b = api_kw["band"]
        assert (b.low, b.high, b.absolute) == (0.8, 1.2, False)


def test_with_defaults_the_table_twins_give_the_commands_numbers(tmp_path, asm_path):
    """`simulate`, `stiffness` and `bearing` with their defaults against their commands with
    theirs: the same table, to the CSV's digits."""
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C,speed_rpm\n0,0\n40,3000\n")
    assert main(["simulate", str(asm_path), str(cond), "-o", str(tmp_path / "s.csv")]) == 0
    _same_frame(bearingfem.simulate(asm_path, cond), _csv(tmp_path / "s.csv"))
    assert main(["stiffness", str(asm_path), str(cond), "-o", str(tmp_path / "k.csv")]) == 0
    _same_frame(bearingfem.stiffness(asm_path, cond).to_frame(), _csv(tmp_path / "k.csv"))
    b, loads = tmp_path / "b.toml", tmp_path / "l.csv"
    b.write_text(BEARING)
    loads.write_text("radial_load_N,axial_load_N,speed_rpm\n500,200,0\n1000,300,6000\n")
    assert main(["bearing", str(b), str(loads), "-o", str(tmp_path / "b.csv")]) == 0
    _same_frame(bearingfem.bearing(b, loads).to_frame(), _csv(tmp_path / "b.csv"))
