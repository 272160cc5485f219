"""Requirements and their traceability: which tests prove each requirement, and how they last ran.

A test proves a requirement by its marker, `@pytest.mark.requirement("R-...")` (registered in
pyproject.toml). `REQUIREMENTS` is the registry (id -> one-line text); tests/test_verify.py holds
every tagged id to it and every registered id to at least one test. When pytest runs, the plugin in
tests/conftest.py records the outcome of every tagged test in the pytest cache
(`RESULTS_RELPATH` under the repository); `bearingfem verify` reads that record (`trace`) and
reports "not run" for a requirement none of whose tests has run there.
"""
from __future__ import annotations

import ast
import json
from dataclasses import dataclass
from pathlib import Path

#: requirement id -> the one-line statement a test proves
REQUIREMENTS: dict[str, str] = {
    "R-FE-MMS-ELASTIC": "The axisymmetric thermo-elastic FE operator (two materials, closed "
                        "frictionless fit) converges at the P2 orders on a manufactured solution: "
                        "displacement h^3 in L2, h^2 in energy.",
    "R-FE-MMS-THERMAL": "The steady conduction FE operator (two conductivities, perfect contact) "
                        "converges at the P2 orders on a manufactured solution.",
    "R-FE-LAME": "FE fit pressures and ring expansions agree with the Lamé thick-ring closed forms "
                 "within 0.5 % (plane stress, plane strain, thermal, clearance fits).",
    "R-FE-ROTATION": "FE fits at speed agree with the rotating-disc closed form within 0.5 % "
                     "(pressure, ring expansion, fit-opening speed).",
    "R-FE-CONTACT": "Fits are exact contact: an open fit carries no force and has the free gap; "
                    "the superposition equals direct FE solves across opening and closing.",
    "R-FE-MESH": "An assembly's mesh meets its target discretisation error (Richardson "
                 "extrapolation over refined meshes).",
    "R-FE-THERMAL": "Steady conduction through a fit matches the closed-form logarithmic profile.",
    "R-HERTZ": "Hertz point contact equals the published closed forms (Johnson) and solves the "
               "Hertz equations.",
    "R-PAIR-EQUILIBRIUM": "The pair's axial equilibrium satisfies Harris's axial-load equation and "
                          "agrees with a second route (prescribed displacement).",
    "R-TORQUE": "The friction-torque components equal direct integration over the contact ellipse "
                "(hysteresis, differential sliding, spin).",
    "R-DIAG-RATES": "The diagnosis keeps its false-claim rate on null data and its hit rate per "
                    "effect (statistical, slow).",
    "R-SEED000-FITS": "The published fit-change rates of study seed000 (-0.05 / +0.07 um/C) and "
                      "outer-fit closing temperature (about 41 C) are reproduced.",
    "R-SEED000-PRELOAD": "The simplified axial stack model of study seed000's paper (its eqs. "
                         "14-20) gives the published preload trend, and bearingfem's axial-only "
                         "part agrees with it.",
}

#: where the conftest plugin records the outcomes (pytest's cache, under the repository)
RESULTS_RELPATH = Path(".pytest_cache") / "v" / "bearingfem" / "requirement_results"


def repository_root() -> Path:
    """The checkout this package runs from (tests/ and .pytest_cache/ sit there)."""
    return Path(__file__).resolve().parents[2]


@dataclass(frozen=True)
class RequirementTrace:
    """One row of the traceability table: the requirement, the tests tagged with it (pytest node
    ids without parameters), and the outcome of their last run ("passed", "failed (k of n)",
    "partly run (k of n): passed", each with ", last run <UTC time>"; or "not run")."""
    id: str
    text: str
    tests: tuple[str, ...]
    result: str

    def to_json(self) -> dict:
        return {"id": self.id, "text": self.text, "tests": list(self.tests), "result": self.result}


def _requirement_ids(dec: ast.expr) -> list[str]:
    """The ids of a `pytest.mark.requirement("...", ...)` decorator, else []."""
    if (isinstance(dec, ast.Call) and isinstance(dec.func, ast.Attribute)
            and dec.func.attr == "requirement"):
        return [a.value for a in dec.args if isinstance(a, ast.Constant) and isinstance(a.value, str)]
    return []


def tagged_tests(tests_dir: Path) -> dict[str, list[str]]:
    """requirement id -> the test node ids ("tests/test_x.py::test_y") carrying its marker,
    read from the test sources (no import, no collection)."""
    out: dict[str, list[str]] = {}
    for path in sorted(tests_dir.glob("test_*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for dec in node.decorator_list:
                    for rid in _requirement_ids(dec):
                        out.setdefault(rid, []).append(f"{tests_dir.name}/{path.name}::{node.name}")
    return out


def read_results(root: Path) -> dict[str, tuple[str, str]]:
    """test node id (parameters stripped) -> (last outcome, when it ran, ISO time), from the
    plugin's record; {} when absent or unreadable. A parametrised test counts as failed if any of
    its cases failed."""
    path = root / RESULTS_RELPATH
    try:
        rec = json.loads(path.read_text())["tests"]
    except (OSError, ValueError, KeyError, TypeError):
        return {}
    out: dict[str, tuple[str, str]] = {}
    rank = {"failed": 2, "passed": 1, "skipped": 0}
    for nodeid, r in rec.items():
        base = nodeid.split("[", 1)[0]
        o, when = r.get("outcome", "skipped"), str(r.get("when", ""))
        if base not in out or rank.get(o, 0) > rank.get(out[base][0], 0):
            out[base] = (o, max(when, out[base][1]) if base in out else when)
    return out


def trace(root: Path | None = None) -> list[RequirementTrace]:
    """The traceability table of the checkout at `root` (default: this package's): every
    registered requirement with its tagged tests and their last outcome."""
    root = repository_root() if root is None else root
    tests_dir = root / "tests"
    tagged = tagged_tests(tests_dir) if tests_dir.is_dir() else {}
    results = read_results(root)
    rows = []
    for rid, text in REQUIREMENTS.items():
        tests = tuple(tagged.get(rid, ()))
        ran = [results[t] for t in tests if t in results and results[t][0] != "skipped"]
        failed = sum(o == "failed" for o, _ in ran)
        if not ran:
            result = "not run"
        elif failed:
            result = f"failed ({failed} of {len(tests)})"
        elif len(ran) < len(tests):
            result = f"partly run ({len(ran)} of {len(tests)}): passed"
        else:
            result = "passed"
        last = max((w for _, w in ran), default="")
        if last:
            result += f", last run {last}"
        rows.append(RequirementTrace(rid, text, tests, result))
    return rows
