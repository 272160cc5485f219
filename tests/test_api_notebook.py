"""A notebook gets what the command line gives (issue: the Python API is the command): the
command's warning lines as `bearingfem.BearingfemWarning`s and on the result, a CSV path (str or
Path) taken like a table, the condition columns first in `simulate`'s table, a loaded `Assembly`
reported with its file as its source, the solver's failures as the package's own ValueError.

The command's lines are the independent side here: they are what `bearingfem simulate` prints on
stderr (run in this process through `studies.app.cli.main`), and the function must reproduce them
word for word. Runs on the template on its coarsest mesh (target error 1 %, as
tests/test_api_commands.py) with two or three rows.
"""
import dataclasses
import re
import warnings

import numpy as np
import pandas as pd
import pytest

import bearingfem
from studies.app.cli import main
from studies.model.config import CONFIG_DIR

COARSE = (CONFIG_DIR / "template.toml").read_text().replace("target_error = 0.001 ",
                                                              "target_error = 0.01  ")
PREFIX = "bearingfem simulate: warning: "
#: the CSV keeps 10 significant digits: a number read back agrees to 5e-10 relative
CSV_RTOL = 1e-9


@pytest.fixture(scope="module")
def asm_path(tmp_path_factory):
    p = tmp_path_factory.mktemp("asm") / "pair.toml"
    p.write_text(COARSE)
    return p


def _command(capsys, *argv) -> list[str]:
    """Run the command; its warning lines (without the prefix)."""
    capsys.readouterr()
    assert main([str(a) for a in argv]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err and all(line.startswith(PREFIX) for line in err), err
    return [line[len(PREFIX):] for line in err]


def _emitted(call) -> tuple[object, list[str]]:
    """The call's result and the BearingfemWarnings it emitted, in order."""
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        out = call()
    return out, [str(w.message) for w in rec if issubclass(w.category, bearingfem.BearingfemWarning)]


@pytest.mark.parametrize("text,expected", [
    # Fahrenheit typed as Celsius (0, 40, 80 C), which also drives the oil past its Walther fit
    ("T_ambient_C,speed_rpm\n32,1000\n104,1000\n176,2000\n", ("Fahrenheit", "extrapolated")),
    # no T_ambient_C, and an axial load that unloads one bearing: two violated limits
    ("speed_rpm,axial_load_N\n1000,0\n2000,3000\n", ("no column T_ambient_C", "rows violate")),
])
def test_a_csv_path_warns_as_the_command_does(tmp_path, asm_path, capsys, text, expected):
    cond = tmp_path / "c.csv"
    cond.write_text(text)
    cli = _command(capsys, "simulate", asm_path, cond, "-o", tmp_path / "o.csv")
    assert all(any(e in line for line in cli) for e in expected), cli
    asm = bearingfem.load_assembly(asm_path)
    for given in (cond, str(cond)):                       # a Path or a str
        sim, emitted = _emitted(lambda: bearingfem.simulate(asm, given))
        assert emitted == cli and sim.attrs["warnings"] == cli
    # the table of the file: condition columns first, the numbers to the file's 10 digits
    file = pd.read_csv(tmp_path / "o.csv")
    assert list(sim.columns) == list(file.columns)
    assert list(sim.columns[:2]) == text.split("\n")[0].split(",")
    for c in file.columns:
        np.testing.assert_allclose(sim[c], file[c], rtol=CSV_RTOL, atol=1e-300, err_msg=c)
    # a notebook's first move: group by a condition
    by_speed = sim.groupby("speed_rpm")["torque_Nmm"].mean()
    assert list(by_speed.index) == sorted(set(file["speed_rpm"]))


def test_an_assembly_changed_in_memory_warns_as_its_file_does(tmp_path, asm_path, capsys):
    """A contact angle in radians: the file given to the command, the same assembly built in
    the notebook from the loaded one (`dataclasses.replace`) given to the function."""
    asm = bearingfem.load_assembly(asm_path)
    rad = dataclasses.replace(asm, bearing=dataclasses.replace(asm.bearing,
                                                               contact_angle_free_deg=0.26))
    bad = tmp_path / "rad.toml"
    bad.write_text(re.sub(r"contact_angle_free_deg = [0-9.]+", "contact_angle_free_deg = 0.26",
                          COARSE, count=1))
    assert bearingfem.load_assembly(bad) == rad               # the same stack both ways
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n20\n")
    cli = _command(capsys, "simulate", bad, cond, "-o", tmp_path / "o.csv")
    assert any("looks like radians" in line for line in cli)
    sim, emitted = _emitted(lambda: bearingfem.simulate(rad, {"T_ambient_C": [20.0]}))
    assert emitted == cli == sim.attrs["warnings"]


def test_a_loaded_assembly_is_reported_with_its_file(asm_path):
    """`report(asm)` with a loaded Assembly: the provenance and the "Inputs and their sources"
    section equal the command's, which is given the path (the full report runs in the slow
    test below)."""
    from studies.model.provenance import file_record
    from studies.usecases import api
    from studies.usecases.report_margins import pedigree_lines

    asm = bearingfem.load_assembly(asm_path)
    by_path = api._provenance("report", asm, asm_path)        # what the command records
    loaded = api._provenance("report", asm, asm)              # what a notebook's call records
    assert loaded["inputs"] == by_path["inputs"] == {"assembly": file_record(asm_path)}
    lines = pedigree_lines(asm, None)
    assert lines == pedigree_lines(asm, asm_path)
    # the template's comments are its sources: every key it sets is listed with its comment
    keys = [ln for ln in "\n".join(lines).splitlines() if ln.startswith("| [")]
    assert len(keys) > 20 and any(ln.startswith("| [preload] assembled_N | 100.0 | N, >= 0")
                                  for ln in keys)
    # an assembly changed after loading is no longer its file
    changed = dataclasses.replace(asm, T_ref_C=asm.T_ref_C + 1.0)
    rec = api._provenance("report", changed, changed)["inputs"]["assembly"]
    assert rec["path"] == f"(in memory: changed after loading {asm_path})"
    assert pedigree_lines(changed, None) != lines


@pytest.mark.slow
def test_a_loaded_assembly_report_names_its_sources(tmp_path, asm_path):
    """The whole report of a loaded Assembly: the header and the sections "Inputs and their
    sources" and the input table of "Environment" equal the command's report of the path."""
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n0\n40\n")
    assert main(["report", str(asm_path), str(cond), "--out", str(tmp_path / "cli")]) == 0
    bearingfem.report(bearingfem.load_assembly(asm_path), cond, out=tmp_path / "py")

    def sections(md: str) -> dict[str, str]:
        parts = md.split("\n## ")
        return {"header": parts[0].split("\n")[2],
                **{p.split("\n")[0]: p for p in parts[1:]}}
    cli = sections((tmp_path / "cli" / "report.md").read_text())
    py = sections((tmp_path / "py" / "report.md").read_text())
    assert py["header"] == cli["header"] and str(asm_path) in py["header"]
    assert py["Inputs and their sources"] == cli["Inputs and their sources"]
    env = lambda s: s[s.index("| input |"):]                              # noqa: E731
    assert env(py["Environment"]) == env(cli["Environment"])


def test_a_solver_failure_is_the_packages_own_error(tmp_path, asm_path, capsys, monkeypatch):
    """A contact solver that does not settle (forced: `Pipeline.run` raising the solver's
    `SolveError`) is, from Python, a `bearingfem.BearingfemError` (a ValueError, as the README
    promises) whose message is the line the command prints before exiting with code 2."""
    from fem.solver import SolveError
    from studies.diagnosis.core import ModelFailure
    from studies.model.pipeline import Pipeline

    line = "contact active set did not settle in 100 iterations"

    def fails(*_args, **_kwargs):
        raise SolveError(line)

    monkeypatch.setattr(Pipeline, "run", fails)
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n20\n")
    capsys.readouterr()
    assert main(["simulate", str(asm_path), str(cond), "-o", str(tmp_path / "o.csv")]) == 2
    assert capsys.readouterr().err == f"bearingfem simulate: {line}\n"
    with pytest.raises(bearingfem.BearingfemError) as exc:
        bearingfem.simulate(asm_path, cond)
    assert isinstance(exc.value, ValueError) and str(exc.value) == line
    assert not (tmp_path / "o.csv").exists()
    # the diagnosis' failure of the model at some parameters, when it reaches the caller
    assert issubclass(ModelFailure, bearingfem.BearingfemError)


def test_tolerance_warns_about_its_inputs_as_the_command_does(tmp_path, capsys, monkeypatch):
    """`tolerance` (and `design`, `diagnose`) check their inputs as `simulate` does: Fahrenheit
    in the conditions is one warning line from the command and the same BearingfemWarning from
    the function. The Monte Carlo itself is replaced by a summary of nothing (only the warning
    is under test; the twins' numbers: tests/test_api_commands.py)."""
    from studies.usecases import tolerance_report

    monkeypatch.setattr(tolerance_report, "run", lambda *a, **k: tolerance_report.ToleranceSummary(
        samples=4, fit_leaves_design={}, preload_lost=0.0))
    asm = tmp_path / "pair.toml"
    asm.write_text(COARSE)
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n32\n176\n")
    capsys.readouterr()
    assert main(["tolerance", str(asm), str(cond), "--samples", "4", "--out",
                 str(tmp_path / "t")]) == 0
    prefix = "bearingfem tolerance: warning: "
    cli = [ln[len(prefix):] for ln in capsys.readouterr().err.splitlines() if ln.startswith(prefix)]
    assert len(cli) == 1 and "Fahrenheit" in cli[0]
    res, emitted = _emitted(lambda: bearingfem.tolerance(asm, cond, samples=4))
    assert emitted == cli and list(res.warnings) == cli
