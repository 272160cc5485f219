"""The assumptions that decide the answer (`bearingfem report`, section "Assumptions that decide
the answer"; `--sensitivity` adds the `[assume]`-tagged numbers and writes `sensitivity.csv`).

An assumption is a modelling choice left at its default or tagged `[assume]` in the assembly
file's comment on that key (`report_margins.assembly_comments`): the clamp kind of the nut and of
the cover, the fit contact model, the preload path's compliance, the ball model, the friction
law and (with `--sensitivity`) the ring section; and each number whose comment carries
`[assume]`. Each is run again with its alternative through the pipeline (the same conditions,
`simulate_table`) and the margin table of the report (`report_margins.margin_rows`, one route)
is formed from that run; every governing number of the table is compared with the report's.

    change = (value_alternative - value) / |value|     (relative, -; NaN when value is 0, ZERO)

`flips`: the margin's PASS and FAIL trade places. Rows are ordered by flips first, then |change|.

Alternatives: a clamp "rigid" <-> "compliant" (the two limits of a clamp with a force, docs/cli.md
"The clamp with a force"); fits "frictionless" <-> "bonded"; preload path "fe" <-> "rigid"; balls
"static" <-> "quasi_dynamic"; oil viscous law "palmgren" <-> "skf2004" (a solid film has no
second law without its shear-strength constants: not varied); ring section "rectangle" <->
"grooved"; a number: NUMBER_STEP up (10 %; a diameter DIAMETER_STEP, 1 %; a temperature
TEMPERATURE_STEP_K, 5 K; the `[assembly]` table's and a `[materials.NAME]` table's numbers too;
a number whose alternative the configuration refuses is listed as not varied, with the reason).
The numbers are compared on the mesh of twice the report's sizes (`NUMBER_MESH_FACTOR`), the
value and its alternative alike: a change of geometry needs its own FE set-up, and the
difference of two runs on one mesh carries less discretisation error than either.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Callable

import numpy as np

from studies.model.config import Assembly
from studies.usecases.report_margins import MarginRow, assembly_comments, margin_rows
from studies.usecases.report_tools import md_table

#: the columns of sensitivity.csv, in order (docs/cli.md "report")
CSV_COLUMNS = ("assumption", "alternative", "margin", "value", "value_alternative", "change",
               "flips")
#: the relative step of an `[assume]`-tagged number, and of a diameter (a key with "diameter"
#: in its name, or the bearing's bore_mm): a section's radial build-up is a few per cent of its diameters, so 10 % of a
#: diameter moves a part past its neighbours (seed000's inner ring section 37.8 -> 41.6 mm
#: past its groove bottom), 1 % is the size of an effective-section assumption
NUMBER_STEP = 0.10
DIAMETER_STEP = 0.01
#: the step of an `[assume]`-tagged temperature (a key in C: T_ref_C), K
TEMPERATURE_STEP_K = 5.0
#: a governing value this close to 0 (in its own unit: N, MPa, deg, rpm, -) is 0: a margin at
#: round-off (a clamp face's force of -6e-9 N) has no relative change
ZERO = 1e-6
#: the numbers' runs are on the mesh of this many times the report's sizes
NUMBER_MESH_FACTOR = 2.0
#: the tag that marks an assumption in an assembly file's comment
TAG = "[assume]"
#: rows of the report's table (every row is in sensitivity.csv)
TABLE_ROWS = 12

#: modelling choices: (section, key, {value: alternative}); `ball_model` is a run option
CHOICES = (("nut", "clamp", {"rigid": "compliant", "compliant": "rigid"}),
           ("cover", "clamp", {"rigid": "compliant", "compliant": "rigid"}),
           ("fits", "contact", {"frictionless": "bonded", "bonded": "frictionless"}),
           ("preload", "path_compliance", {"fe": "rigid", "rigid": "fe"}),
           ("operating", "ball_model", {"static": "quasi_dynamic", "quasi_dynamic": "static"}),
           ("lubrication", "viscous_model", {"palmgren": "skf2004", "skf2004": "palmgren"}),
           ("mesh", "ring_section", {"rectangle": "grooved", "grooved": "rectangle"}))
#: choices the short version (the report without --sensitivity) leaves out: a grooved section
#: is a finer mesh, the slowest set-up (33 s against 7 s for a clamp on this machine)
LONG_ONLY = {("mesh", "ring_section")}


@dataclass(frozen=True)
class Alternative:
    """One assumption and its alternative: `assumption` as the report names it ("[cover] clamp =
    rigid (default)"), `alternative` the value tried, `asm` the assembly with it, `number`:
    a tagged number (run on the coarser mesh)."""
    assumption: str
    alternative: str
    asm: Assembly
    number: bool = False


@dataclass(frozen=True)
class SensitivityRow:
    """One line of sensitivity.csv: an assumption's alternative and one governing number of the
    margin table (`margin`, unit in its name), its value as the report has it and under the
    alternative, their relative change and whether PASS and FAIL trade places."""
    assumption: str
    alternative: str
    margin: str
    value: float
    value_alternative: float
    change: float
    flips: bool
    item: str = ""          # the margin table's row it comes from (for the text)
    status: str = ""        # PASS / FAIL / no limit, as the report has it
    status_alternative: str = ""


@dataclass(frozen=True)
class Sensitivity:
    """What the section and the CSV are made of: the rows (ordered), the assumptions not varied
    (with the reason) and whether this is the long version (`--sensitivity`)."""
    rows: tuple[SensitivityRow, ...]
    skipped: tuple[str, ...]
    long: bool

    @property
    def flips(self) -> list[SensitivityRow]:
        return [r for r in self.rows if r.flips]


def _default(section, key: str):
    return next(f.default for f in fields(section) if f.name == key)


def _tagged(comments: dict, section: str, key: str) -> bool:
    return TAG in comments.get((section, key), "")


def alternatives(asm: Assembly, assembly_path: Path | None, long: bool
                 ) -> tuple[list[Alternative], list[str]]:
    """The assumptions of `asm` and their alternatives (module docstring), and the ones not
    varied with the reason. The `[assume]` tags are the comments of the file `asm` was loaded
    from, else of `assembly_path` (`report_margins.assembly_comments`; none: every choice at
    its default is still an assumption)."""
    from studies.model.config import ConfigError
    from studies.model.config_checks import check_assembly

    comments = assembly_comments(asm, assembly_path)
    out, skipped = [], []

    def add(name: str, alt_text: str, alt: Assembly, number: bool = False):
        try:
            check_assembly(alt, "alternative")
        except ConfigError as exc:
            skipped.append(f"{name} -> {alt_text}: {str(exc).removeprefix('alternative: ')}")
            return
        out.append(Alternative(name, alt_text, alt, number))

    for section, key, alt_of in CHOICES:
        if not long and (section, key) in LONG_ONLY:
            continue
        sec = getattr(asm, section)
        value = getattr(sec, key)
        default = value == _default(type(sec), key)
        if not (default or _tagged(comments, section, key)) or value not in alt_of:
            continue
        if section == "lubrication" and asm.lubrication.kind != "oil":
            skipped.append(f"[lubrication] {key}: a solid film has no second law without its "
                           "shear-strength constants")
            continue
        name = f"[{section}] {key} = {value}" + (" (default)" if default else " [assume]")
        add(name, alt_of[value], replace(asm, **{section: replace(sec, **{key: alt_of[value]})}))
    if not long:
        return out, skipped
    for (section, key), comment in comments.items():
        found = _number(asm, section, key) if TAG in comment else None
        if found is None:
            continue            # untagged, a text, a list, or a zero (no relative step)
        value, with_value = found
        step = DIAMETER_STEP if "diameter" in key or key == "bore_mm" else NUMBER_STEP
        if key.endswith("_C"):              # a temperature: no relative step in Celsius
            new, how = value + TEMPERATURE_STEP_K, f"+{TEMPERATURE_STEP_K:g} K"
        else:
            new = (type(value)(round(value * (1 + step))) if isinstance(value, int)
                   else value * (1 + step))
            how = f"+{100 * step:g} %"
        if new == value:
            continue
        add(f"[{section}] {key} = {value:g} [assume]", f"{new:.6g} ({how})", with_value(new),
            number=True)
    return out, skipped


def _number(asm: Assembly, section: str, key: str):
    """(value, value -> the assembly with it) of a numeric key of the file: a section's, the
    `[assembly]` table's (T_ref_C) or a `[materials.NAME]` table's (`analytic.materials`
    TABLE_KEYS: E_MPa, nu, cte_per_K, ...); None for a text, a list, a zero or another table."""
    from analytic.materials import TABLE_KEYS

    if section.startswith("materials."):
        name, field = section.removeprefix("materials."), TABLE_KEYS.get(key)
        mat = next((m for m in asm.materials if m.name == name), None)
        if mat is None or field is None or key == "source":
            return None
        value = getattr(mat, field)

        def with_value(v):
            return replace(asm, materials=tuple(replace(m, **{field: v}) if m.name == name else m
                                                for m in asm.materials))
    elif section == "assembly":
        value = getattr(asm, key, None)

        def with_value(v):
            return replace(asm, **{key: v})
    elif hasattr(asm, section):
        sec = getattr(asm, section)
        value = getattr(sec, key, None)

        def with_value(v):
            return replace(asm, **{section: replace(sec, **{key: v})})
    else:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value == 0:
        return None
    return value, with_value


def margins_of(asm: Assembly, cond: dict, pipeline) -> list[MarginRow]:
    """The report's margin table (`report_margins.margin_rows`, no mesh errors) of `asm` under
    the conditions `cond`, run through `pipeline` (the one route: `simulate_table`)."""
    from studies.model.columns import to_columns
    from studies.model.pipeline import simulate_table

    res = to_columns(simulate_table(asm, cond, pipeline=pipeline))
    return margin_rows(asm, res, res, {}, cond)


def compare(assumption: str, alternative: str, base: list[MarginRow], alt: list[MarginRow]
            ) -> list[SensitivityRow]:
    """The governing numbers of two margin tables side by side (module docstring), one row per
    number both have."""
    by_key = {r.key: r for r in alt if r.key}
    out = []
    for b in base:
        a = by_key.get(b.key)
        if a is None or not b.key:
            continue
        v, w = float(b.value), float(a.value)
        if not (math.isfinite(v) and math.isfinite(w)):
            continue
        change = ((w - v) / abs(v) if abs(v) > ZERO
                  else 0.0 if abs(w) <= ZERO else float("nan"))
        flips = b.passes is not None and a.passes is not None and b.passes != a.passes
        out.append(SensitivityRow(assumption, alternative, b.key, v, w, change, flips, b.item,
                                  b.status, a.status))
    return out


def order(rows: list[SensitivityRow]) -> list[SensitivityRow]:
    """Flips first, then the largest |change| (a change from 0, NaN, after the finite ones)."""
    return sorted(rows, key=lambda r: (not r.flips, math.isnan(r.change),
                                       -abs(r.change) if not math.isnan(r.change) else 0.0))


def run(asm: Assembly, cond: dict, base_rows: list[MarginRow], assembly_path: Path | None,
        mesh_factor: float, long: bool, progress: Callable[[str], None] = lambda s: None
        ) -> Sensitivity:
    """Every assumption of `asm` against the report's margin table `base_rows` (the report's
    mesh, `mesh_factor`); the numbers against their own base on NUMBER_MESH_FACTOR times it."""
    from meshes.build import MeshError
    from studies.model.pipeline import Pipeline

    alts, skipped = alternatives(asm, assembly_path, long)
    rows: list[SensitivityRow] = []
    coarse_base = None
    for k, alt in enumerate(alts, 1):
        progress(f"report: assumption {k} of {len(alts)}: {alt.assumption} -> {alt.alternative}")
        factor = mesh_factor * (NUMBER_MESH_FACTOR if alt.number else 1.0)
        try:
            if alt.number and coarse_base is None:
                coarse_base = margins_of(asm, cond, Pipeline(asm, mesh_factor=factor))
            theirs = margins_of(alt.asm, cond, Pipeline(alt.asm, mesh_factor=factor))
        except (ValueError, MeshError) as exc:   # the package's errors: no answer for this one
            skipped.append(f"{alt.assumption} -> {alt.alternative}: no answer ({exc})")
            continue
        rows += compare(alt.assumption, alt.alternative, coarse_base if alt.number else base_rows,
                        theirs)
    return Sensitivity(tuple(order(rows)), tuple(skipped), long)


def _pct(x: float) -> str:
    return "from 0" if math.isnan(x) else f"{100 * x:+.3g} %"


def section_lines(s: Sensitivity) -> list[str]:
    """Markdown section "Assumptions that decide the answer": the flips as warnings, then per
    assumption and alternative the governing number it moves most, largest first."""
    lines = ["## Assumptions that decide the answer", "",
             "Each modelling choice left at its default or tagged `[assume]` in the assembly file"
             + (" and each `[assume]`-tagged number (+10 %, a diameter +1 %, a temperature "
                "+5 K, on the mesh of twice the sizes)" if s.long else "")
             + ", run again with its alternative over the same operating points; the margin "
               "table of each run beside the one above (change: relative to the report's value)."
             + ("" if s.long else " `bearingfem report --sensitivity` adds the ring section and "
                "the `[assume]`-tagged numbers and writes sensitivity.csv."), ""]
    for r in s.flips:
        lines.append(f"- **Warning**: {r.assumption} -> {r.alternative} turns {r.item} from "
                     f"{r.status} to {r.status_alternative} ({r.margin} {r.value:.4g} -> "
                     f"{r.value_alternative:.4g}).")
    if s.flips:
        lines.append("")
    best: dict[tuple[str, str], SensitivityRow] = {}
    for r in s.rows:                       # ordered: the first of each pair moves it most
        best.setdefault((r.assumption, r.alternative), r)
    table = order(list(best.values()))[:TABLE_ROWS]
    if table:
        lines += [md_table(["assumption", "alternative", "moves most", "value",
                            "with the alternative", "change", "PASS/FAIL flips"],
                           [[r.assumption, r.alternative, f"{r.item} (`{r.margin}`)",
                             f"{r.value:.4g}",
                             f"{r.value_alternative:.4g}", _pct(r.change),
                             "yes" if r.flips else ""] for r in table]), ""]
    else:
        lines += ["No assumption to vary.", ""]
    if s.skipped:
        lines += ["Not varied: " + "; ".join(s.skipped) + ".", ""]
    return lines


def write_csv(path: Path, s: Sensitivity, provenance: dict | None = None) -> None:
    """sensitivity.csv (columns CSV_COLUMNS; `flips` true/false, `change` nan when the value is
    0) through the project's one CSV writer (`studies.model.table.write_table`, atomic, with the
    provenance sidecar)."""
    from studies.model.table import write_table

    r = s.rows
    write_table(path, {
        "assumption": np.array([x.assumption for x in r], str),
        "alternative": np.array([x.alternative for x in r], str),
        "margin": np.array([x.margin for x in r], str),
        "value": np.array([x.value for x in r], float),
        "value_alternative": np.array([x.value_alternative for x in r], float),
        "change": np.array([x.change for x in r], float),
        "flips": np.array(["true" if x.flips else "false" for x in r], str)}, provenance)


def frame(s: Sensitivity):
    """The rows as a `pandas.DataFrame` with the CSV's columns."""
    import pandas as pd

    return pd.DataFrame([[getattr(r, c) for c in CSV_COLUMNS] for r in s.rows],
                        columns=list(CSV_COLUMNS))
