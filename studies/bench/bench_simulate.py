"""`bearingfem bench --simulate`: what a user waits for and how much memory it takes, printed
(never asserted by a test).

Every number is one whole `bearingfem simulate` process (interpreter start, imports, set-up,
evaluation, writing), run as a child of this one:
- per assembly (the shipped ones, plus any `--assembly`): a 3-row simulate with an empty cache
  folder (BEARINGFEM_CACHE: meshing, assembly, factorisation, unit solutions) and again with the
  cache it left (the FE set-up read from disk); the best of two warm runs; DOF of the FE model;
  peak resident memory (ru_maxrss of the child);
- seed000 with 1e5 and 1e6 condition rows (1e4 and 1e5 with `--quick`): time, peak memory and
  the memory per row between the two sizes.
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass(frozen=True)
class ChildRun:
    """One child process: wall time (s), peak resident memory (bytes), exit code."""
    seconds: float
    peak_bytes: int
    code: int


def run_simulate(assembly: Path, conditions: Path, out: Path, cache: Path) -> ChildRun:
    """`bearingfem simulate assembly conditions -o out` in a child process with BEARINGFEM_CACHE
    = cache; its wall time and ru_maxrss (kB on Linux)."""
    env = dict(os.environ, BEARINGFEM_CACHE=str(cache))
    env.pop("BEARINGFEM_VERBOSE", None)
    cmd = [sys.executable, "-m", "studies.app.cli", "simulate", str(assembly), str(conditions),
           "-o", str(out)]
    with open(out.with_suffix(".stderr"), "w") as err:
        t0 = time.perf_counter()
        p = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=err)
        _, status, usage = os.wait4(p.pid, 0)
        seconds = time.perf_counter() - t0
    p.returncode = os.waitstatus_to_exitcode(status)
    return ChildRun(seconds, 1024 * usage.ru_maxrss, p.returncode)


def _conditions(path: Path, n: int) -> Path:
    T = np.random.default_rng(1).uniform(-60.0, 80.0, n)
    with open(path, "w") as fh:
        fh.write("T_ambient_C\n")
        for a in range(0, n, 100_000):
            fh.write("".join(f"{t:.3f}\n" for t in T[a:a + 100_000]))
    return path


def _dofs(assembly: Path, cache: Path) -> int:
    """DOF of the assembly's FE model, from the set-up the runs left in `cache`."""
    from studies.model.config import load_assembly
    from studies.model.pipeline import Pipeline

    old = os.environ.get("BEARINGFEM_CACHE")
    os.environ["BEARINGFEM_CACHE"] = str(cache)
    try:
        return Pipeline(load_assembly(assembly)).ndofs
    finally:
        if old is None:
            os.environ.pop("BEARINGFEM_CACHE")
        else:
            os.environ["BEARINGFEM_CACHE"] = old


def _check(run: ChildRun, what: str, out: Path) -> ChildRun:
    if run.code != 0:
        msg = out.with_suffix(".stderr").read_text().strip().splitlines()
        raise RuntimeError(f"{what}: simulate exited {run.code}: {msg[-1] if msg else ''}")
    return run


def main(quick: bool = False, assemblies: tuple[Path, ...] = ()) -> None:
    from studies.model.config import CONFIG_DIR, SHIPPED

    paths = sorted(CONFIG_DIR.glob("*.toml")) + [Path(a) for a in assemblies]
    with tempfile.TemporaryDirectory(prefix="bearingfem-bench-") as tmp:
        tmp = Path(tmp)
        three = tmp / "c3.csv"
        three.write_text("T_ambient_C\n-40\n20\n80\n")
        print("== simulate of 3 rows, whole process (cold: empty cache folder; warm: its second "
              "run, best of two) ==")
        print(f"{'assembly':32s} {'DOF':>7s} {'cold s':>7s} {'warm s':>7s} {'cold GB':>8s} "
              f"{'warm GB':>8s}")
        for asm in paths:
            cache, out = tmp / f"cache_{asm.stem}", tmp / f"{asm.stem}.csv"
            cold = _check(run_simulate(asm, three, out, cache), asm.name, out)
            warm = min((_check(run_simulate(asm, three, out, cache), asm.name, out)
                        for _ in range(2)), key=lambda r: r.seconds)
            print(f"{asm.stem:32s} {_dofs(asm, cache):7d} {cold.seconds:7.2f} {warm.seconds:7.2f} "
                  f"{cold.peak_bytes / 1e9:8.3f} {warm.peak_bytes / 1e9:8.3f}")
        asm = CONFIG_DIR / SHIPPED["seed000"]
        sizes = (10_000, 100_000) if quick else (100_000, 1_000_000)
        print(f"== simulate memory, {asm.stem}, warm cache, T_ambient_C only ==")
        print(f"{'rows':>9s} {'s':>8s} {'peak GB':>8s} {'us/row':>7s}")
        runs = {}
        cache = tmp / f"cache_{asm.stem}"
        for n in sizes:
            cond, out = _conditions(tmp / f"c{n}.csv", n), tmp / f"o{n}.csv"
            runs[n] = r = _check(run_simulate(asm, cond, out, cache), f"{n} rows", out)
            print(f"{n:9d} {r.seconds:8.1f} {r.peak_bytes / 1e9:8.3f} {1e6 * r.seconds / n:7.0f}")
            out.unlink()
        a, b = sizes
        per_row = (runs[b].peak_bytes - runs[a].peak_bytes) / (b - a)
        print(f"peak memory per row between {a} and {b} rows: {per_row:.0f} bytes")
    if not quick:
        _accuracy(paths)


def _accuracy(paths) -> None:
    """The chosen mesh's achieved discretisation error per assembly: its x1 level against the
    Richardson value of its x1, x0.5, x0.25 meshes (verify.mesh_convergence_case, the tests'
    reference from finer meshes only)."""
    from studies.model.config import load_assembly
    from studies.usecases.verify import mesh_convergence_case

    print("== chosen mesh: target and achieved error (vs Richardson of x1, x0.5, x0.25) ==")
    print(f"{'assembly':32s} {'target':>8s} {'achieved':>9s}")
    for path in paths:
        c = mesh_convergence_case(load_assembly(path), factors=(1.0, 0.5, 0.25), used=0)
        target = c.assessment.target_error
        print(f"{path.stem:32s} {'given' if target is None else f'{target:.1e}':>8s} "
              f"{c.assessment.error_max:9.2e}")
