"""infra/: atomic output without touching the umask, the stale-temporary sweeper, the in-memory
cache helper. Expected values come from POSIX (a new file's mode is 0666 less the umask, a folder's
0777 less it; a PID that no process has is dead) and from the rules stated in the docstrings."""
import os
import threading
import time
from dataclasses import dataclass

import numpy as np
import pytest

from infra.files import HOST_TAG, STALE_AGE_S, AtomicFile, atomic_folder, sweep_stale, write_atomic
from infra.memo import Memo, inputs_key
from studies.app.output import atomic_dir
from studies.model.table import write_table

DEAD_PID = 2 ** 22 + 12345           # above the default pid_max: no such process


@pytest.fixture()
def umask_027(monkeypatch):
    """umask 027 set, then any call of os.umask fails: reading and restoring the umask races with
    other threads (a thread creating a file between the two calls gets mode 0666)."""
    old = os.umask(0o027)

    def no_umask(mask):
        raise AssertionError("os.umask called: not thread-safe")
    monkeypatch.setattr(os, "umask", no_umask)
    yield
    monkeypatch.undo()
    os.umask(old)


def test_outputs_get_their_modes_without_reading_the_umask(tmp_path, umask_027):
    write_table(tmp_path / "t.csv", {"a": np.array([1.0])}, provenance={"command": "x"})
    assert os.stat(tmp_path / "t.csv").st_mode & 0o777 == 0o640
    assert os.stat(tmp_path / "t.csv.json").st_mode & 0o777 == 0o640
    os.chmod(tmp_path / "t.csv", 0o600)                      # a replaced file keeps its mode
    write_table(tmp_path / "t.csv", {"a": np.array([2.0])})
    assert os.stat(tmp_path / "t.csv").st_mode & 0o777 == 0o600
    with atomic_dir(tmp_path / "out") as d:
        (d / "x.txt").write_text("x")
    assert os.stat(tmp_path / "out").st_mode & 0o777 == 0o750


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "new" / "f.txt"
    with pytest.raises(RuntimeError):
        with AtomicFile(target) as fh:
            fh.write("half")
            raise RuntimeError("interrupted")
    assert not (tmp_path / "new").exists()                   # the folder made for it is gone
    write_atomic(target, "old")
    with pytest.raises(RuntimeError):
        with atomic_folder(tmp_path / "d") as d:
            (d / "x").write_text("x")
            raise RuntimeError("interrupted")
    assert target.read_text() == "old" and sorted(os.listdir(tmp_path)) == ["new"]
    assert os.listdir(tmp_path / "new") == ["f.txt"]


def test_the_sweeper_removes_what_runs_that_are_gone_left(tmp_path):
    other_host = "0" * 8 if HOST_TAG != "0" * 8 else "1" * 8
    names = {"dead": f".o.csv.{DEAD_PID}.{HOST_TAG}00000000",
             "alive": f".o.csv.{os.getpid()}.{HOST_TAG}00000001",
             "other machine": f".o.csv.{DEAD_PID}.{other_host}00000002",
             "no pid, fresh": ".o.csv.abc123",
             "no pid, old": ".o.csv.abc456",
             "other output": f".p.csv.{DEAD_PID}.{HOST_TAG}00000003",
             "dead folder": f".o.csv.{DEAD_PID}.{HOST_TAG}00000004"}
    for what, name in names.items():
        p = tmp_path / name
        p.mkdir() if "folder" in what else p.write_text(what)
    old = time.time() - STALE_AGE_S - 60
    os.utime(tmp_path / names["no pid, old"], (old, old))
    removed = {p.name for p in sweep_stale(tmp_path, ".o.csv.")}
    assert removed == {names[k] for k in ("dead", "no pid, old", "dead folder")}
    assert {p.name for p in tmp_path.iterdir()} == set(names.values()) - removed


def test_memo_drops_the_least_recently_used_and_keeps_its_budget():
    m = Memo(max_items=3, max_size=10)
    for k in "abc":
        m.put(k, k.upper(), size=2)
    assert m.get("a") == "A"                   # a used: b is now the least recently used
    m.put("d", "D", size=2)
    assert "b" not in m and {k for k in "acd" if k in m} == set("acd")
    m.put("e", "E", size=7)                    # 2 + 2 + 2 + 7 > 10: a and c go, in that order
    assert "a" not in m and "c" not in m and "d" in m and "e" in m
    m.put("huge", "H", size=11)                # larger than the whole budget: not kept
    assert "huge" not in m and len(m) == 2


def test_memo_copies_when_asked_and_makes_once():
    m = Memo(copy=True)
    value = {"x": np.zeros(3)}
    m.put("k", value)
    value["x"][0] = 1.0                        # the caller changes what it put ...
    got = m.get("k")
    got["x"][1] = 2.0                          # ... and what it got: the memo holds neither
    assert np.array_equal(m.get("k")["x"], np.zeros(3))
    calls = []
    plain = Memo()
    make = lambda: calls.append(1) or object()  # noqa: E731
    assert plain.get_or_make("y", make) is plain.get_or_make("y", make) and len(calls) == 1


def test_read_only_memo_hands_back_what_nobody_can_modify_without_copying():
    """A read-only memo (the pair equilibria's): what `put` returns and every `get` hands back is
    one object whose arrays, in nested frozen dataclasses and tuples, are read-only views of the
    values put (equal, no copy); a write into them raises; the caller's own arrays stay
    writeable."""
    @dataclass(frozen=True)
    class Inner:
        a: np.ndarray

    @dataclass(frozen=True)
    class Outer:
        x: np.ndarray
        inner: Inner
        pair: tuple
        name: str = "s"

    value = Outer(np.arange(3.0), Inner(np.ones(2)), (np.zeros(2), None))
    m = Memo(read_only=True)
    kept = m.put("k", value)
    assert m.get("k") is kept and m.get_or_make("k", lambda: 1 / 0) is kept
    arrays = (kept.x, kept.inner.a, kept.pair[0])
    for got, mine in zip(arrays, (value.x, value.inner.a, value.pair[0])):
        assert np.shares_memory(got, mine) and np.array_equal(got, mine)
        with pytest.raises(ValueError, match="read-only"):
            got[0] = 5.0
        mine[0] = mine[0]                      # the caller's arrays stay writeable
    assert kept.pair[1] is None and kept.name == "s"
    with pytest.raises(ValueError):
        Memo(copy=True, read_only=True)


def test_memo_under_threads_keeps_its_limits():
    m = Memo(max_items=8, max_size=20)
    errors = []

    def work(seed):
        rng = np.random.default_rng(seed)
        try:
            for _ in range(2000):
                k = int(rng.integers(0, 30))
                if m.get(k) is None:
                    m.put(k, k, size=float(rng.integers(1, 4)))
        except Exception as exc:           # pragma: no cover - reported below
            errors.append(exc)
    threads = [threading.Thread(target=work, args=(i,)) for i in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and len(m) <= 8
    sizes = [s for _, s in m._items.values()]
    assert sum(sizes) <= 20 and m._size == pytest.approx(sum(sizes), abs=1e-9)


def test_inputs_key_sees_dtype_shape_and_bytes():
    a = np.arange(4.0)
    assert inputs_key({"a": a}) == inputs_key({"a": a.copy()})
    assert len({inputs_key({"a": a}), inputs_key({"a": a.reshape(2, 2)}),
                inputs_key({"a": a.astype(np.float32)}), inputs_key({"b": a})}) == 4
