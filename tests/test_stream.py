"""simulate in chunks (studies/model/stream.py, table.iter_table, table.TableWriter): the streamed
table and its check summaries are those of the whole table computed at once, bad input anywhere
stops the run before any FE work with one line and no output, and memory beyond a chunk does not
grow with the rows."""
import csv
import os
import re
import tracemalloc

from types import SimpleNamespace

import numpy as np
import pytest

from studies.app.cli import main
from studies.model import stream
from studies.model.checks import assembly_checks, evaluate_checks, plausibility_warnings
from studies.model.config import CONFIG_DIR, load_shipped
from studies.model.pipeline import ModelError, Pipeline, check_answers, simulate_table
from studies.model.stream import CheckTally, check_conditions, simulate_file
from studies.model.table import TableError, TableWriter, iter_table, read_table, write_table
from studies.model.columns import to_columns

CFG = CONFIG_DIR / "seed000_71807C_TC4.toml"


@pytest.fixture(scope="module")
def pipes():
    return {name: Pipeline(load_shipped(name), mesh_factor=3.0) for name in ("seed000", "seed003")}


def conditions(path, n, seed=3, hot=False):
    rng = np.random.default_rng(seed)
    T = rng.uniform(201.0, 290.0, n) if hot else rng.uniform(-60.0, 80.0, n)
    speed, load = rng.uniform(0, 6000, n), rng.uniform(-30, 30, n)
    path.write_text("time_s,T_ambient_C,T_shaft_C,speed_rpm,axial_load_N\n" + "".join(
        f"{10 * i},{T[i]:.3f},{T[i] + 4 * rng.random():.3f},{speed[i]:.1f},{load[i]:.2f}\n"
        for i in range(n)))
    return path


def parsed(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array(rows[1:], float)


@pytest.mark.parametrize("name,effects,hot", [
    ("seed000", {}, False),
    ("seed000", {"interference_error": {"inner_um": -5.5}, "thermal_lag": {"tau_s": 40.0}}, False),
    ("seed003", {}, True),          # kelvin, viscous-torque and land warnings, every row
])
def test_streamed_table_and_summaries_are_the_whole_tables(tmp_path, pipes, name, effects, hot):
    pl = pipes[name]
    asm = pl.asm
    cond = conditions(tmp_path / "c.csv", 23, hot=hot)
    runs = {}
    for chunk in (23, 5):
        out = tmp_path / f"o{chunk}.csv"
        runs[chunk] = simulate_file(asm, cond, out, effects, pipeline=pl, chunk_rows=chunk)
    assert (tmp_path / "o5.csv").read_bytes() == (tmp_path / "o23.csv").read_bytes()
    # the whole table at once, through the functions simulate used before it streamed
    whole = read_table(cond)
    result = simulate_table(asm, whole, effects, pipeline=pl)
    res = to_columns(result, friction_split=True)   # simulate's columns, flags and margins too
    violations = result.checks.violations()
    cols = {**{k: v for k, v in whole.items() if k != "_line"}, **res}
    header, table = parsed(tmp_path / "o5.csv")
    assert header == list(cols) and table.shape == (23, len(cols))
    for j, k in enumerate(header):          # printed with 10 significant digits
        v = np.asarray(cols[k], float)
        assert np.array_equal(np.isnan(table[:, j]), np.isnan(v)), k   # empty = not stated
        if np.isnan(v).all():
            continue
        assert np.nanmax(np.abs(table[:, j] - v)) <= 5e-10 * np.nanmax(np.abs(v)), k
    run = runs[5]
    assert run.n_rows == 23
    assert [(v.check, v.rows.tolist(), v.worst_row, v.worst_value) for v in run.violations] == \
        [(v.check, v.rows.tolist(), v.worst_row, v.worst_value) for v in violations]
    assert run.summaries() == [v.summary(23, whole) for v in violations]
    assert run.warnings == plausibility_warnings(asm, cols, res)
    if hot:
        assert len(run.warnings) >= 3 and any("kelvin" in w for w in run.warnings)
    if effects:
        assert any(v.check.name == "fit_open_inner" for v in run.violations)


def test_check_tally_equals_the_checks_of_the_whole_table():
    asm = load_shipped("seed000")
    checks = assembly_checks(asm)
    rng = np.random.default_rng(5)
    n = 200
    p, s0, P = (rng.choice([4000.0, 4300.0, 4500.0], n), rng.choice([2.0, 2.5, 4.0], n),
                rng.choice([0.0, 50.0], n))
    fi, fo = rng.uniform(-1, 5, n), rng.uniform(-1, 5, n)

    def rows(a, b):             # what the checks read of a result, rows a..b
        return SimpleNamespace(pair=SimpleNamespace(max_contact_pressure_MPa=p[a:b], preload_N=P[a:b]),
                               summary=SimpleNamespace(static_safety=s0[a:b]),
                               fits=SimpleNamespace(inner_MPa=fi[a:b], outer_MPa=fo[a:b]))

    whole = evaluate_checks(rows(0, n), checks)
    expect = whole.violations()                                # equal worst values in many rows
    for cuts in ([0, n], [0, 1, 2, 77, 150, n], list(range(0, n + 1, 9)) + [n]):
        tally = CheckTally(checks)
        parts = []
        for a, b in zip(cuts, cuts[1:]):
            if b > a:
                parts.append(evaluate_checks(rows(a, b), checks))
                tally.add(parts[-1], a)
        got = tally.violations()
        assert [(v.check, v.rows.tolist(), v.worst_row, v.worst_value) for v in got] == \
            [(v.check, v.rows.tolist(), v.worst_row, v.worst_value) for v in expect]
        for k, o in enumerate(whole.outcomes):
            np.testing.assert_array_equal(
                np.concatenate([c.outcomes[k].violated for c in parts]), o.violated)


def test_chunks_put_together_are_the_table(tmp_path):
    p = tmp_path / "c.csv"
    p.write_bytes(b"\xef\xbb\xbf# a comment\r\ntime_s,T_ambient_C\r\n\r\n" + b"".join(
        f"{i},{20 + i % 7}\r\n".encode() for i in range(10)) + b"# end\n")
    whole = read_table(p)
    chunks = list(iter_table(p, chunk_rows=3))
    assert [len(c["_line"]) for c in chunks] == [3, 3, 3, 1]
    for k in whole:
        np.testing.assert_array_equal(np.concatenate([c[k] for c in chunks]), whole[k])
    assert whole["_line"][0] == 4                              # lines as in the file
    assert check_conditions(p, chunk_rows=3) == 10


def test_time_must_increase_across_a_chunk_boundary(tmp_path):
    p = tmp_path / "c.csv"
    p.write_text("time_s,T_ambient_C\n0,20\n1,20\n2,20\n2,20\n")
    with pytest.raises(TableError, match=r"line 5, column 'time_s': time not increasing"):
        list(iter_table(p, chunk_rows=3))


@pytest.mark.parametrize("bom", [b"", b"\xef\xbb\xbf"])
def test_a_byte_that_is_not_utf8_is_named_by_its_offset(tmp_path, bom):
    p = tmp_path / "c.csv"
    p.write_bytes(bom + b"T_ambient_C\n20\n3\xff0\n")          # 12 + 3 + 1 bytes before it
    with pytest.raises(TableError, match="invalid start byte at byte 16"):
        read_table(p)


def test_a_bad_row_late_in_the_file_stops_simulate_before_any_fe_work(tmp_path, capsys, monkeypatch):
    def no_fe(*a, **k):
        raise AssertionError("the FE was set up")
    monkeypatch.setattr(Pipeline, "shared", no_fe)
    n = stream.CHUNK_ROWS + 40                                 # the bad row is in the second chunk
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n" + "20\n" * (n - 1) + "-400\n")
    out = tmp_path / "o.csv"
    code = main(["simulate", str(CFG), str(cond), "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and f"line {n + 1}, column 'T_ambient_C': -400" in err[0], err
    assert not out.exists() and not list(tmp_path.glob(".o.csv*"))


def test_an_error_in_a_later_chunk_leaves_no_output(tmp_path, pipes, monkeypatch):
    pl = pipes["seed000"]
    cond = conditions(tmp_path / "c.csv", 12)
    real, calls = Pipeline.run, []

    def failing(self, inputs, *a, **k):
        calls.append(k.get("first_row"))
        if len(calls) == 3:
            raise ModelError("row 11: planted")
        return real(self, inputs, *a, **k)
    monkeypatch.setattr(Pipeline, "run", failing)
    out = tmp_path / "sub" / "o.csv"
    with pytest.raises(ModelError, match="row 11"):
        simulate_file(pl.asm, cond, out, {}, provenance={"command": "test"}, pipeline=pl,
                      chunk_rows=5)
    assert calls == [0, 5, 10]
    assert not (tmp_path / "sub").exists()                    # no table, sidecar, temp or folder


def test_model_errors_name_the_row_of_the_whole_table():
    out = {k: np.ones(4) for k in ("torque_Nmm", "preload_N", "contact_angle_deg",
                                   "fit_pressure_inner_MPa", "fit_pressure_outer_MPa",
                                   "max_contact_pressure_MPa")}
    with pytest.raises(ModelError, match="^row 20003: the bearing"):
        check_answers(out, np.array([True, True, False, True]), first_row=20000)
    out["preload_N"] = np.array([1.0, np.nan, 1.0, 1.0])
    with pytest.raises(ModelError, match="^row 20002: preload_N"):
        check_answers(out, np.ones(4, bool), first_row=20000)


def test_table_writer_in_chunks_writes_write_tables_bytes(tmp_path):
    cols = {"a": np.linspace(-1, 1, 11), "b": np.arange(11) > 4, "_line": np.arange(11)}
    write_table(tmp_path / "whole.csv", cols)
    with TableWriter(tmp_path / "parts.csv") as w:
        for a, b in ((0, 4), (4, 5), (5, 11)):
            w.write({k: v[a:b] for k, v in cols.items()})
    assert (tmp_path / "parts.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    with pytest.raises(KeyboardInterrupt):
        with TableWriter(tmp_path / "new" / "x.csv", provenance={"command": "test"}) as w:
            w.write(cols)
            raise KeyboardInterrupt
    assert not (tmp_path / "new").exists()


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_memory_beyond_a_chunk_does_not_grow_with_the_rows(tmp_path, pipes):
    """Peak traced memory of a streamed run of 1400 rows against one of 200 rows, chunks of
    20 (a warm-up run first). The fixed part (about 560 kB) varies by +-15 kB with what ran before
    in the process, so the rows differ by 1200 (+-13 B a row of noise). What grows with the
    rows is what the summaries read over all rows: the kept columns (T_ambient_C, T_shaft_C and
    the four WARNING_OUTPUTS, 48 bytes a row), the temporaries of the warnings over them (a mask
    and three arrays of loaded rows, 25 bytes a row) and the indices of violating rows (none
    here): under 120 bytes a row, against about 8 kB a row when all rows were evaluated at once
    (the goal: under 1 kB)."""
    pl = pipes["seed000"]
    peaks = {}
    for n in (200, 1400):
        cond = conditions(tmp_path / f"c{n}.csv", n)
        simulate_file(pl.asm, cond, tmp_path / "warm.csv", {}, pipeline=pl, chunk_rows=20)
        tracemalloc.start()
        simulate_file(pl.asm, cond, tmp_path / f"o{n}.csv", {}, pipeline=pl, chunk_rows=20)
        peaks[n] = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    per_row = (peaks[1400] - peaks[200]) / 1200
    assert per_row < 120, (peaks, per_row)


def test_simulate_on_two_dask_workers_writes_the_single_process_bytes(tmp_path, pipes):
    """The chunks of a simulate evaluated as Dask tasks (a local cluster of 2 worker processes,
    each building its own FE set-up at the pipeline's mesh factor) give the bytes of the
    single-process run, table and check summaries alike; effects that depend on earlier rows
    (a thermal lag) included."""
    pl = pipes["seed000"]
    cond = conditions(tmp_path / "c.csv", 23)
    effects = {"thermal_lag": {"tau_s": 40.0}}
    for tag, eff in (("plain", {}), ("lag", effects)):
        here = simulate_file(pl.asm, cond, tmp_path / f"{tag}_here.csv", eff, pipeline=pl,
                             chunk_rows=5)
        dask = simulate_file(pl.asm, cond, tmp_path / f"{tag}_dask.csv", eff, pipeline=pl,
                             chunk_rows=5, workers=2)
        assert (tmp_path / f"{tag}_dask.csv").read_bytes() == (tmp_path / f"{tag}_here.csv").read_bytes()
        assert dask.summaries() == here.summaries() and dask.warnings == here.warnings


def test_row_formatting_reads_back_to_ten_digits_and_matches_the_per_value_writer(tmp_path):
    """table.format_rows (the vectorised CSV of numeric columns): every number read back with
    Python's float is the value to 10 significant digits (relative 5e-10, half a unit of the
    10th digit), -0, inf and nan as written by '%.10g', booleans 1/0, integers exact; and the
    text is that of csv.writer with one format call per value (the writer used for text columns)."""
    import io

    from studies.model import table

    rng = np.random.default_rng(0)
    n = 500
    x = rng.normal(size=n) * 10.0 ** rng.integers(-30, 30, n)
    x[:5] = [0.0, -0.0, np.inf, -np.inf, np.nan]
    flags, ints = rng.random(n) < 0.5, rng.integers(-10**6, 10**6, n)
    text = table.format_rows([x, flags, ints])
    rows = [line.split(",") for line in text.splitlines()]
    assert text.endswith("\n") and len(rows) == n
    back = np.array([float(r[0]) for r in rows])
    np.testing.assert_allclose(back[5:], x[5:], rtol=5e-10, atol=0)
    assert [r[0] for r in rows[:5]] == ["0", "-0", "inf", "-inf", "nan"]
    assert [r[1] for r in rows] == ["1" if f else "0" for f in flags]
    assert [int(r[2]) for r in rows] == ints.tolist()
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    for i in range(n):
        w.writerow([table._fmt(a[i]) for a in (x, flags, ints)])
    assert text == buf.getvalue()


def test_simulate_with_an_unreachable_scheduler_is_one_line_and_no_output(tmp_path, capsys,
                                                                        monkeypatch):
    """--scheduler at an address nothing listens on: exit 2, one line naming the address, no
    output file."""
    from studies.model import parallel

    monkeypatch.setattr(parallel, "CONNECT_TIMEOUT_S", 2.0)
    cond = conditions(tmp_path / "c.csv", 3)
    out = tmp_path / "o.csv"
    code = main(["simulate", str(CFG), str(cond), "-o", str(out), "--scheduler", "tcp://127.0.0.1:9"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and not out.exists()
    assert len(err) == 1 and "--scheduler tcp://127.0.0.1:9: cannot connect" in err[0], err


def test_the_table_being_written_is_a_hidden_temporary_named_by_this_process(tmp_path):
    """While rows are written the table is `.NAME.<pid>.<16 hex>` beside NAME (what the sweeper of
    a later run reads the PID from); an error inside the block leaves nothing."""
    out = tmp_path / "o.csv"
    with pytest.raises(KeyboardInterrupt):
        with TableWriter(out, provenance={"command": "test"}) as w:
            w.write({"T_ambient_C": np.array([20.0, 40.0])})
            (tmp,) = tmp_path.iterdir()
            assert re.fullmatch(rf"\.o\.csv\.{os.getpid()}\.[0-9a-f]{{16}}", tmp.name), tmp.name
            raise KeyboardInterrupt
    assert not list(tmp_path.iterdir())
