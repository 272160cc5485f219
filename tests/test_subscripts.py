"""Typed data in the product code: string-keyed subscripts (`x["name"]`, `x[f"..."]`)
in the product packages stay at most MAX_STRING_SUBSCRIPTS. Counted with an AST walk; tests, the
studies (`studies/validation`, `studies/bench`) and the file/CLI edge writers and readers, whose
job is named columns and keys, are not counted."""
from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

PRODUCT = ("infra", "analytic", "meshes", "fem", "studies/model", "studies/diagnosis",
           "studies/usecases", "bearingfem")
#: the edge: CSV/TOML/JSON in and out, named columns, the command line
EDGE = {"studies/model/table.py", "studies/model/columns.py", "studies/model/provenance.py",
        "studies/model/config.py", "studies/model/config_docs.py", "studies/diagnosis/result.py",
        "studies/diagnosis/files.py", "studies/diagnosis/report.py"}
#: 582 on 2026-11-29 before the verify and ball-model records; 448 after
MAX_STRING_SUBSCRIPTS = 450


def string_subscripts(source: str) -> int:
    return sum(1 for node in ast.walk(ast.parse(source)) if isinstance(node, ast.Subscript) and (
        isinstance(node.slice, ast.JoinedStr) or (isinstance(node.slice, ast.Constant)
                                                  and isinstance(node.slice.value, str))))


def product_count() -> dict[str, int]:
    out = {}
    for pkg in PRODUCT:
        for f in sorted((ROOT / pkg).rglob("*.py")):
            rel = f.relative_to(ROOT).as_posix()
            if rel not in EDGE:
                out[rel] = string_subscripts(f.read_text())
    return out


def test_the_counter_counts_string_keys_only():
    assert string_subscripts('a["x"]; b[f"{k}_N"]; c[0]; d[k]; e["y"]["z"]') == 4


def test_product_code_keeps_its_string_keyed_subscripts_bounded():
    per = product_count()
    worst = sorted(per.items(), key=lambda kv: -kv[1])[:5]
    assert sum(per.values()) <= MAX_STRING_SUBSCRIPTS, worst
