"""The front of the engineer's report (`bearingfem report`): the margin table, the inputs with
their pedigree, the numbered assumptions, the credibility table, the environment and the command
that reproduces it (docs/cli.md, "report").

Everything here is read from what the run already computed: the result columns, the flag and
margin columns of studies/model/checks.py (`evaluate_checks`), the discretisation error of the
assembly's mesh (`studies.usecases.verify.mesh_convergence_case`), the traceability record of the
tests (`studies.usecases.requirements`). Nothing is recomputed but the headline numbers on the next
finer mesh of the same family, for their discretisation error.

Mesh error of a headline number (Richardson extrapolation, Roache 1998 ch. 5): with the value
f_1 on the mesh used and f_h on the mesh of half its sizes (`Section.scaled(0.5)`), and the
order p of the mesh family in its factor (studies/model/mesh_size.py ORDER = 1.5),

    error(f_1) ~= |f_1 - f_h| * 2^p / (2^p - 1) / |f_1|           (relative, -)
"""
from __future__ import annotations

import os
import platform
import re
import shlex
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path

import numpy as np

from studies.model.provenance import comments_in, origin_of
from studies.usecases.report_tools import condition_text, md_table

if TYPE_CHECKING:
    from studies.usecases.verify import ConvergenceCase

_at = condition_text          # the governing point by its condition

#: the packages whose versions the "Environment" section lists
PACKAGES = ("numpy", "scipy", "scikit-fem", "gmsh", "meshio", "matplotlib", "pyvista", "pandas",
            "markdown", "typst")
#: fits the pipeline may report (studies/model/checks.py flags those assembled with interference)
FITS = ("inner", "outer", "sleeve", "cartridge")


@dataclass(frozen=True)
class MarginRow:
    """One line of the margin table. `value_text`: the range or governing value over the
    operating points; `margin_text`: the margin column of the check at its governing point (or
    the distance to a zero limit); `status`: "PASS", "FAIL" or "no limit"; `mesh_error`: the
    relative discretisation error of the governing value (None: not an FE-dependent number).
    `key`: the governing number's name, unit in it (the `margin` of sensitivity.csv); `value`:
    that number (NaN: none)."""
    item: str
    value_text: str
    allowable_text: str
    margin_text: str
    status: str
    mesh_error: float | None
    source: str
    key: str = ""
    value: float = float("nan")

    @property
    def passes(self) -> bool | None:
        """True for PASS, False for FAIL, None without a limit."""
        return (True if self.status == "PASS" else False if self.status.startswith("FAIL")
                else None)


@dataclass(frozen=True)
class Headline:
    """A headline number: the column, which row governs (min or max) and its value."""
    column: str
    row: int
    value: float


def headlines(res: dict) -> dict[str, Headline]:
    """The numbers of the margin table: name -> (column, governing row, value)."""
    out = {}

    def add(name, col, use_max):
        v = np.asarray(res[col], float)
        i = int(np.argmax(v) if use_max else np.argmin(v))
        out[name] = Headline(col, i, float(v[i]))
    add("preload_min", "preload_N", False)
    add("preload_max", "preload_N", True)
    add("contact_pressure_max", "max_contact_pressure_MPa", True)
    for fit in FITS:
        if f"fit_pressure_{fit}_MPa" in res:
            add(f"fit_{fit}_min", f"fit_pressure_{fit}_MPa", False)
            add(f"fit_{fit}_max", f"fit_pressure_{fit}_MPa", True)
    if "margin_clamp_N" in res:                          # a clamp with a force
        add("clamp_margin_min", "margin_clamp_N", False)
        add("clamp_force_min", "clamp_force_N", False)
        add("clamp_force_max", "clamp_force_N", True)
    add("static_safety_min", "static_safety", False)
    add("torque_min", "torque_Nmm", False)
    add("torque_max", "torque_Nmm", True)
    return out


def headline_mesh_errors(cond: dict, res: dict, fine_pipeline, order: float) -> dict[str, float]:
    """Relative discretisation error of each headline number (module docstring): the governing
    rows run again through the pipeline on the finer mesh. An open fit (zero pressure on either
    mesh) has no error to speak of: NaN."""
    from studies.model.columns import to_columns
    from studies.model.pipeline import simulate_table

    hl = headlines(res)
    rows = sorted({h.row for h in hl.values()})
    sub = {k: np.asarray(v)[rows] for k, v in cond.items()}
    fine = to_columns(simulate_table(fine_pipeline.asm, sub, pipeline=fine_pipeline), flags=False)
    gain = 2.0 ** order / (2.0 ** order - 1.0)
    out = {}
    for name, h in hl.items():
        f_h = float(np.asarray(fine[h.column])[rows.index(h.row)])
        out[name] = (abs(h.value - f_h) * gain / abs(h.value)
                     if h.value != 0 and f_h != 0 else float("nan"))
    return out


def margin_rows(asm, res: dict, flags: dict, mesh_error: dict[str, float],
                cond: dict | None = None) -> list[MarginRow]:
    """The margin table from the result, flag and margin columns (no check recomputed), and the
    thermal speed limits of each bearing (`thermal_speed_rows`, from `cond`)."""
    from studies.model.checks import assembly_checks

    checks = {c.name: c for c in assembly_checks(asm)}
    hl = headlines(res)
    n = len(np.asarray(res["preload_N"]))

    def status(flag):
        bad = int(np.sum(np.asarray(flags[flag]) > 0))
        return "PASS" if bad == 0 else f"FAIL ({bad} of {n})"

    rows = []
    lo, hi = hl["preload_min"], hl["preload_max"]
    rows.append(MarginRow(
        "preload band", f"{lo.value:.4g} .. {hi.value:.4g} N", "> 0 N",
        f"{lo.value:.4g} N above 0 ({_at(cond, lo.row)})", status("flag_preload_lost"),
        _worst(mesh_error, "preload_min", "preload_max"), checks["preload_lost"].source,
        "preload_min_N", lo.value))
    c, h = checks["max_contact_pressure_MPa"], hl["contact_pressure_max"]
    rows.append(MarginRow(
        "peak contact pressure", f"{h.value:.4g} MPa", f"<= {c.allowable:g} MPa",
        f"{float(np.asarray(flags['margin_max_contact_pressure_MPa'])[h.row]):+.3f} ({_at(cond, h.row)})",
        status("flag_max_contact_pressure_MPa"), mesh_error.get("contact_pressure_max"), c.source,
        "max_contact_pressure_MPa", h.value))
    rows += preload_limit_rows(asm, res, cond) + land_rows(asm, res, cond)
    for fit in FITS:
        if f"fit_{fit}_min" not in hl:
            continue
        h = hl[f"fit_{fit}_min"]
        p = np.asarray(res[f"fit_pressure_{fit}_MPa"], float)
        n_open = int(np.sum(p <= 0))
        state = "closed" if n_open == 0 else ("open" if n_open == n else f"open in {n_open} of {n}")
        chk = checks.get(f"fit_open_{fit}")
        rows.append(MarginRow(
            f"{fit} fit ({state})", f"{h.value:.4g} .. {float(np.max(p)):.4g} MPa",
            "> 0 MPa" if chk else "clearance fit: may open",
            f"{h.value:.4g} MPa above 0 ({_at(cond, h.row)})" if chk else "",
            status(f"flag_fit_open_{fit}") if chk else "no limit",
            _worst(mesh_error, f"fit_{fit}_min", f"fit_{fit}_max"),
            chk.source if chk else "designed with clearance", f"fit_pressure_{fit}_min_MPa",
            h.value))
    if "clamp_margin_min" in hl:
        c, h = checks["clamp_open"], hl["clamp_margin_min"]
        lo, hi = hl["clamp_force_min"], hl["clamp_force_max"]
        rows.append(MarginRow(
            "clamp force", f"{lo.value:.4g} .. {hi.value:.4g} N", "> the axial load (N)",
            f"{h.value:.4g} N left ({_at(cond, h.row)})", status("flag_clamp_open"),
            _worst(mesh_error, "clamp_force_min", "clamp_force_max"), c.source,
            "margin_clamp_min_N", h.value))
    c, h = checks["static_safety"], hl["static_safety_min"]
    rows.append(MarginRow(
        "static safety s0", f"{h.value:.4g}", f">= {c.allowable:g}",
        f"{float(np.asarray(flags['margin_static_safety'])[h.row]):+.3f} ({_at(cond, h.row)})",
        status("flag_static_safety"), mesh_error.get("static_safety_min"), c.source,
        "static_safety_min", h.value))
    rows += thermal_speed_rows(asm, cond, res)
    lo, hi = hl["torque_min"], hl["torque_max"]
    rows.append(MarginRow(
        "friction torque", f"{lo.value:.4g} .. {hi.value:.4g} N mm", "none given",
        _torque_interval_text(asm, lo.value, hi.value, res.get("heat_W")),
        "no limit", _worst(mesh_error, "torque_min", "torque_max"), "no torque limit in the assembly",
        "torque_max_Nmm", hi.value))
    return rows


def _torque_interval_text(asm, lo_Nmm: float, hi_Nmm: float, heat_W=None) -> str:
    """The friction law's model-form interval on the torque range (`analytic.friction.interval`,
    from study friction_validation's published points) and, with the rows' friction heat
    `heat_W` (W; the torque times the speed, the same factors), on the heat range, with its
    level and measured leave-one-source-out coverage (`interval_text`), or why none is
    stated."""
    from analytic.friction.interval import interval_text, lubrication_interval
    i = lubrication_interval(asm.lubrication)
    if not i.stated:
        return interval_text(i)
    a, b = i.apply(lo_Nmm)[0], i.apply(hi_Nmm)[1]
    heat = ""
    if heat_W is not None and np.size(heat_W):
        q = np.asarray(heat_W, float)
        heat = (f", heat {i.apply(np.nanmin(q))[0]:.4g} .. {i.apply(np.nanmax(q))[1]:.4g} W "
                f"(nominal {np.nanmin(q):.4g} .. {np.nanmax(q):.4g} W)")
    return f"{a:.4g} .. {b:.4g} N mm{heat}: " + interval_text(i)


def preload_limit_rows(asm, res: dict, cond: dict | None) -> list[MarginRow]:
    """The preload's upper limit: the largest preload against the bearing's basic static load
    rating C0 (ISO 76:2006 eq. 1 from the bearing's geometry, `analytic.safety`; the limit
    `[preload] assembled_N` is held to), margin C0 / max - 1 at the governing point."""
    from analytic.safety import static_load_rating_C0_N

    b = asm.bearing
    C0 = float(static_load_rating_C0_N(b.ball_count, b.ball_diameter_mm, b.pitch_diameter_mm,
                                       b.contact_angle_free_deg))
    p = np.asarray(res["preload_N"], float)
    i = int(np.argmax(p))
    n_over = int(np.sum(p > C0))
    return [MarginRow("preload upper limit (C0)", f"max {p[i]:.4g} N", f"<= C0 = {C0:.4g} N",
                      f"{C0 / p[i] - 1.0:+.3f} ({_at(cond, i)})" if p[i] > 0 else "",
                      "PASS" if n_over == 0 else f"FAIL ({n_over} of {p.size})", None,
                      "ISO 76:2006 eq. 1 (C0 from the bearing's geometry)", "preload_max_N",
                      float(p[i]))]


def land_rows(asm, res: dict, cond: dict | None) -> list[MarginRow]:
    """The contact ellipse against the groove edge (land), inner and outer: the smallest angle
    between the ellipse's edge and the land over the operating points (`land_margin_<side>_deg`,
    analytic/bearing/land.py); below 0 the ellipse is truncated (FAIL)."""
    rows = []
    for side in ("inner", "outer"):
        col = f"land_margin_{side}_deg"
        if col not in res:
            continue
        m = np.asarray(res[col], float)
        i = int(np.argmin(m))
        bad = int(np.sum(m < 0))
        given = getattr(asm.bearing, f"{side}_land_diameter_mm") > 0
        rows.append(MarginRow(
            f"{side} land (contact ellipse edge)", f"{m[i]:.3g} .. {float(np.max(m)):.3g} deg",
            "> 0 deg (ellipse inside the groove)", f"{m[i]:.3g} deg ({_at(cond, i)})",
            "PASS" if bad == 0 else f"FAIL ({bad} of {m.size})", None,
            "analytic/bearing/land.py; land diameter "
            + ("from [bearing]" if given else "inferred from the ring section"), col, float(m[i])))
    return rows


def _row_values(cond: dict, n: int, *names, default: float) -> np.ndarray:
    """The first of the condition columns `names` present, else `default`, as (n,) floats."""
    for c in names:
        if c in cond:
            return np.asarray(cond[c], float) * np.ones(n)
    return np.full(n, float(default))


def thermal_speed_rows(asm, cond: dict | None, res: dict) -> list[MarginRow]:
    """One margin row per bearing (A, B): the ISO 15312 thermal reference speed and the DIN 732
    thermally permissible speed (`studies.usecases.bearing_single.thermal_speeds`, the bearing
    command's route) at each operating point: the bearing's axial force (result
    `axial_force_<J>_N`) and the speed (speed_rpm, else [lubrication] speed_rpm); the oil at the
    permissible temperature (DIN 732's heat balance). margin_speed_rpm = permissible - speed at the
    governing point (the smallest margin); without an oil only the reference speed."""
    from analytic.bearing.geometry import BearingGeometry
    from studies.usecases.bearing_single import thermal_speeds

    cond = cond or {}
    n = len(np.asarray(res["preload_N"]))
    lub = asm.lubrication
    speed = _row_values(cond, n, "speed_rpm", default=lub.speed_rpm)
    g = BearingGeometry.from_spec(asm.bearing, asm.materials)
    rows = []
    for J in ("A", "B"):
        if f"axial_force_{J}_N" not in res:
            continue
        ts = thermal_speeds(asm.bearing, g, lub, asm.oil(), res[f"axial_force_{J}_N"], speed)
        ref = f"reference {ts.reference.speed_rpm:.4g} rpm (ISO 15312)"
        src = "ISO 15312:2018; DIN 732:2010, friction ISO/TR 14179-2"
        if ts.defaults:
            src += "; defaults: " + ", ".join(ts.defaults)
        margin = ts.margin_speed_rpm
        if not np.any(np.isfinite(margin)):
            rows.append(MarginRow(f"thermal speed, bearing {J}", ref, "no oil: no DIN 732 limit",
                                  "", "no limit", None, src, f"margin_thermal_speed_{J}_rpm"))
            continue
        i = int(np.nanargmin(margin))
        perm = ts.permissible_speed_rpm
        rows.append(MarginRow(
            f"thermal speed, bearing {J}",
            (f"{float(np.min(speed)):.4g} .. {float(np.max(speed)):.4g} rpm" if np.ptp(speed) > 0
             else f"{float(speed[0]):.4g} rpm") + f"; {ref}",
            f"<= {float(np.nanmin(perm)):.4g} .. {float(np.nanmax(perm)):.4g} rpm (DIN 732)",
            f"{margin[i]:+.4g} rpm ({_at(cond, i)})" + _upper_end_text(ts.margin_speed_hi_rpm, n),
            "PASS" if margin[i] >= 0 else f"FAIL ({int(np.sum(margin < 0))} of {n})", None, src,
            f"margin_thermal_speed_{J}_rpm", float(margin[i])))
    return rows


def _upper_end_text(margin_hi, n: int) -> str:
    """The speed margin at the upper end of the friction law's model-form interval (the friction
    heat times its upper factor), or nothing where no interval is stated."""
    m = np.asarray(margin_hi if margin_hi is not None else np.nan, float)
    if not np.any(np.isfinite(m)):
        return ""
    bad = int(np.sum(m < 0))
    return (f"; at the friction interval's upper end {float(np.nanmin(m)):+.4g} rpm"
            + (f" (below the speed in {bad} of {n} rows)" if bad else ""))


def _clamp_text(asm, name: str) -> str:
    """A clamp as the assumptions name it: its kind, and a force clamp's force and stiffness
    (`studies.model.stack.clamp_stiffness_N_per_mm`: given, or from its section)."""
    from studies.model.stack import clamp_stiffness_N_per_mm

    c = getattr(asm, name)
    if c.clamp != "force":
        return c.clamp
    k = 1e-3 * clamp_stiffness_N_per_mm(asm, name)
    how = "given" if c.clamp_stiffness_N_per_um > 0 else "from its section, VDI 2230"
    return (f"{c.clamp_force_N:g} N force, {k:.4g} N/um in series ({how}); its face and the "
            "stack's faces on its side (ring-shoulder, ring-spacer) are contacts that open when "
            "the force is used up")


def _worst(err: dict, *names) -> float | None:
    vals = [err[k] for k in names if k in err and np.isfinite(err[k])]
    return max(vals) if vals else None


def _err_text(e: float | None) -> str:
    return "" if e is None or not np.isfinite(e) else f"{100 * e:.2g} %"


def margin_lines(rows: list[MarginRow], n_points: int, where: str) -> list[str]:
    """Markdown section "Margins" (first in the report)."""
    return ["## Margins", "",
            f"Over {n_points} operating points ({where}); every check `simulate` applies "
            "(studies/model/checks.py), the margin at the governing point (allowable / actual - 1 "
            "for an upper limit, actual / allowable - 1 for a lower one; for a zero limit the "
            "distance to it); mesh error: the discretisation error of the governing value "
            "(Richardson, see Credibility).", "",
            md_table(["item", "over the operating range", "allowable", "margin", "PASS/FAIL",
                      "mesh error", "allowable from"],
                     [[r.item, r.value_text, r.allowable_text, r.margin_text, r.status,
                       _err_text(r.mesh_error), r.source] for r in rows]), ""]


# ------------------------------------------------------------------------------- pedigree
def config_comments(path: Path) -> dict[tuple[str, str], str]:
    """(table, key) -> the comment on that key's line in the assembly file (its own pedigree:
    the template asks for the source of every number in its comment; `provenance.comments_in`)."""
    try:
        return comments_in(Path(path).read_text(encoding="utf-8-sig"))
    except OSError:
        return {}


def assembly_comments(asm, assembly_path: Path | None) -> dict[tuple[str, str], str]:
    """The comments of the file `asm` was loaded from (its text as read then), else of the file
    named (`config_comments`), else none."""
    origin = origin_of(asm)
    return (comments_in(origin.text) if origin is not None else
            config_comments(assembly_path) if assembly_path else {})


def material_references() -> dict[str, str]:
    """Material source key -> its full reference, from analytic/materials.py's source list."""
    from analytic import materials

    refs, key = {}, None
    for line in (materials.__doc__ or "").splitlines():
        m = re.match(r"\s*\[([^\]]+)\]\s+(.*)", line)
        if m:
            key = m.group(1)
            refs[key] = m.group(2).strip()
        elif key and line.startswith("      ") and line.strip():
            refs[key] += " " + line.strip()
        else:
            key = None
    return refs


def pedigree_lines(asm, assembly_path: Path | None) -> list[str]:
    """Markdown section "Inputs and their sources": each material with its reference, the
    bearing's catalogue sources, every key of the assembly with the comment it carries, the
    tolerance classes."""
    from analytic.catalogue import CATALOGUE

    refs = material_references()
    mats = {}
    for part in ("shaft", "housing", "nut", "cover", "inner_spacer", "outer_spacer", "inner_ring",
                 "ball", *(n for n, _ in asm.layers())):
        m = asm.material(part)
        mats.setdefault(m.name, [m, []])[1].append(part)
    mat_rows = [[name, ", ".join(parts), f"{m.E_MPa:.6g}", f"{m.nu:g}", f"{m.alpha_per_K * 1e6:.4g}",
                 f"[{m.source}] {refs.get(m.source, '')}".strip()]
                for name, (m, parts) in mats.items()]
    comments = assembly_comments(asm, assembly_path)
    cat = CATALOGUE.get(asm.bearing.designation)
    key_rows = []
    for name in ("shaft", "housing", "nut", "cover", "inner_spacer", "outer_spacer", "bearing",
                 "fits", "preload", "lubrication", "limits", "operating"):
        sec = getattr(asm, name)
        for f in fields(sec):
            src = comments.get((name, f.name))
            if src is None and name == "bearing" and cat is not None and f.name in cat.sources:
                src = f"catalogue {asm.bearing.designation}: {cat.sources[f.name]}"
            if src is None:
                continue                     # not in the file: a default (the echo lists it)
            key_rows.append([f"[{name}] {f.name}", str(getattr(sec, f.name)), src])
    f = asm.fits
    classes = [("inner shaft seat", f.inner_shaft_class or _limits(f.inner_shaft_deviation_um)),
               ("inner ring bore", f.inner_ring_bore_class or _limits(f.inner_ring_bore_deviation_um)),
               ("housing bore", f.outer_housing_class or _limits(f.outer_housing_deviation_um)),
               ("outer ring OD", f.outer_ring_od_class or _limits(f.outer_ring_od_deviation_um))]
    for n, _ in asm.layers():
        classes += [(f"{n} OD", getattr(f, f"{n}_shaft_class")
                     or _limits(getattr(f, f"{n}_shaft_deviation_um"))),
                    (f"bore the {n} sits in", getattr(f, f"{n}_bore_class")
                     or _limits(getattr(f, f"{n}_bore_deviation_um")))]
    tol = ("Tolerance classes (ISO 286 seats, ISO 492 rings; analytic/tolerances.py): "
           + "; ".join(f"{k} {v or 'none given'}" for k, v in classes)
           + f"; deviations {f.distribution} within their limits.")
    return ["## Inputs and their sources", "",
            f"Assembly: {asm.source or 'no source given'}.", "",
            md_table(["material", "parts", "E (MPa)", "nu", "CTE (1e-6/K)", "source"], mat_rows), "",
            tol, "", *([asm.oil().statement(), ""] if asm.oil() is not None else []),
            "Each key of the assembly file with the source its comment gives (keys not in the "
            "file take their documented defaults; the full echo is under Inputs below):", "",
            md_table(["key", "value", "source (comment in the assembly file)"], key_rows), ""]


def _limits(dev) -> str:
    return "" if not dev else f"limits {tuple(dev)} um"


# ---------------------------------------------------------------------------- assumptions
def assumption_lines(asm) -> list[str]:
    """Markdown section "Assumptions", numbered; those that follow from the configuration name
    the key that sets them."""
    ball = {"static": "quasi-static balls (no centrifugal force or gyroscopic moment)",
            "quasi_dynamic": "quasi-dynamic balls (centrifugal force, gyroscopic moment, "
                             f"{asm.operating.raceway_control} raceway control)"}
    items = [
        "The stack is axisymmetric (shaft, rings, spacers, nut, cover, housing in one r-z "
        "section); radial load and moment act on the pair's analytic model, not on the FE.",
        "Linear elastic, small strain, P2 elements; material properties constant except the "
        "CTE law of analytic/materials.py.",
        "Each part at one uniform temperature per operating point (parts without their own "
        "column follow the ambient temperature).",
        f"Fits are exact contact, {asm.fits.contact} (`[fits] contact`); an interference fit may "
        "open, a clearance fit may close.",
        f"Fits and preload ({asm.preload.kind} preload, {asm.preload.assembled_N:g} N) are set at "
        f"T_ref = {asm.T_ref_C:g} C; with tolerance classes the fits are the middle of their bands.",
        f"Clamps: nut {_clamp_text(asm, 'nut')}; cover {_clamp_text(asm, 'cover')} (`[nut] clamp`, "
        "`[cover] clamp`; \"rigid\" and \"compliant\" are the limits of a clamp with a force: "
        "infinitely stiff and never opening, or without force and stiffness).",
        "The rings' deformation enters the bearing model only through the groove-centre shifts "
        f"of the FE ({asm.mesh.ring_section} ring sections, `[mesh] ring_section`); "
        "Hertz point contact at each ball, pair equilibrium; " + ball[asm.operating.ball_model] + ".",
        "Friction torque: hysteresis, differential sliding, spin, load and viscous (Palmgren) "
        f"terms (analytic/torque.py); {asm.lubrication.kind} lubrication.",
        "Discretisation: the mesh sized by studies/model/mesh_size.py for its target error; the "
        "error achieved is in Credibility.",
    ]
    return ["## Assumptions", ""] + [f"{i}. {t}" for i, t in enumerate(items, 1)] + [""]


# ---------------------------------------------------------------------------- credibility
#: the model compared with published measurements: (case, published, what is compared and how
#: closely, the test that asserts it (None: printed by the study only))
VALIDATION = (
    ("study seed000: fit-change rates", "-0.05 / +0.07 um/C (inner / outer)",
     "within 0.005 um/C", "tests/test_verify_seed000.py::"
     "test_fit_rates_and_closing_temperature_are_the_published_ones"),
    ("study seed000: outer clearance closing temperature", "about 41 C", "within 0.5 K",
     "tests/test_verify_seed000.py::test_fit_rates_and_closing_temperature_are_the_published_ones"),
    ("study seed000: preload trend (the paper's simplified axial model, its eqs. 14-20; "
     "analytic/axial_stack.py)", "-40 .. +40 N over -60 .. 80 C (its Fig. 9b)",
     "sign and monotonic rise, within 50 % of the size; this model's axial part between the "
     "limits of that stack (the radial effects it leaves out reverse the cold end)",
     "tests/test_verify_seed000.py::test_the_papers_axial_model_gives_the_published_trend"),
    ("study seed001: torque ratios against 20 C", "+33 .. 50 % at -20 C, -25 % at 60 C",
     "printed beside the published ones by `bearingfem study seed001`", None),
    ("study seed003: ball-screw support heat at 1000 / 1500 rpm", "heat-up measured on the rig",
     "printed by `bearingfem study seed003`; the heat balance is asserted, not the measurement",
     None),
)


#: the quantities whose worst case over the tolerance bands the report gives
TOLERANCE_QUANTITIES = ("preload_N", "max_contact_pressure_MPa", "fit_pressure_inner_MPa",
                        "fit_pressure_outer_MPa", "torque_Nmm")


def tolerance_lines(asm, res: dict, worst=None) -> list[str]:
    """The uncertainty from the fit tolerances: the worst case of the interference bands (four
    corners, `studies.usecases.tolerance_report.worst_case`) beside the mid-band result."""
    if worst is None:
        return ["Uncertainty from the fit tolerances: no tolerance classes or limit deviations "
                "in `[fits]`; the fits are as given.", ""]
    layers = [n for n, _ in asm.layers()]
    qs = TOLERANCE_QUANTITIES + tuple(f"fit_pressure_{n}_MPa" for n in layers)
    rows = [[q, f"{np.min(res[q]):.4g} .. {np.max(res[q]):.4g}",
             f"{np.min(getattr(worst, q)):.4g}", f"{np.max(getattr(worst, q)):.4g}"]
            for q in qs]
    bands = ("the four corners of the two interference bands" if not layers else
             f"the {2 ** (2 + len(layers))} corners of the {2 + len(layers)} interference bands "
             f"(inner, outer, {', '.join(layers)})")
    return [f"Uncertainty from the fit tolerances: {bands} "
            "(every deviation at a limit) at every operating point, beside the mid-band result "
            "above; the Monte Carlo and the probabilities: `bearingfem tolerance`.", "",
            md_table(["quantity", "mid-band (this report)", "worst case min", "worst case max"],
                     rows), ""]


def credibility_lines(conv: ConvergenceCase, mesh_error: dict[str, float], order: float,
                      traces=None, test_results=None, tolerance: list[str] = ()) -> list[str]:
    """Markdown section "Credibility": code verification (the requirement traceability of
    `verify`, last results of their tests), this mesh's error, the validation cases and
    their agreement, input pedigree, the tolerance uncertainty."""
    from studies.usecases.requirements import read_results, repository_root, trace

    traces = trace() if traces is None else traces
    results = read_results(repository_root()) if test_results is None else test_results
    req_rows = [[t.id, t.text, t.result] for t in traces]
    val_rows = []
    for case, pub, how, test in VALIDATION:
        res = "not asserted by a test" if test is None else \
            " ".join(results.get(test, ("not run here", ""))).strip()
        val_rows.append([case, pub, how, res])
    target = conv.assessment.target_error
    err_rows = [[name, _err_text(e)] for name, e in mesh_error.items()]
    return ["## Credibility", "",
            "### Code verification", "",
            "Requirements and the last results of the tests that prove them in this checkout "
            "(studies/usecases/requirements.py; `bearingfem verify` writes the same table with the "
            "manufactured-solution orders and the Lamé cases into verification.json).", "",
            md_table(["requirement", "statement", "last result"], req_rows), "",
            "### This mesh's error", "",
            f"Largest error of the FE quantities that feed the bearing model (fit pressures, "
            f"groove-centre shifts) against their Richardson values: {100 * conv.assessment.error_max:.2g} %"
            + ("" if target is None else f" (target {100 * target:g} %: "
               f"{'met' if conv.assessment.within_target else 'NOT met'})")
            + ". Headline numbers: relative error from the mesh used and the mesh of half its "
              f"sizes, |f1 - fh| 2^p / (2^p - 1) / |f1| with p = {order:g} (Roache 1998):", "",
            md_table(["headline number", "mesh error"], err_rows), "",
            "### Validation", "",
            "The published measurements the model has been compared with (the published rigs of "
            "`bearingfem study`) and their agreement:", "",
            md_table(["case", "published", "agreement", "test result"], val_rows), "",
            "### Input pedigree and uncertainty", "",
            "Sources of every material and catalogue value and of each assembly key: "
            "\"Inputs and their sources\" above.", ""] + list(tolerance)


# ---------------------------------------------------------------------- environment, command
def report_date() -> str:
    """The report's date (UTC): SOURCE_DATE_EPOCH when set (reproducible builds), else now."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    t = datetime.fromtimestamp(int(epoch), timezone.utc) if epoch else datetime.now(timezone.utc)
    return t.strftime("%Y-%m-%d %H:%M UTC")


def environment_lines(prov: dict) -> list[str]:
    """Markdown section "Environment": tool, Python, packages, the SHA-256 of each input."""
    def version(p):
        try:
            return metadata.version(p)
        except metadata.PackageNotFoundError:
            return "not installed"
    rows = [["bearingfem", str(prov.get("version", ""))],
            ["Python", platform.python_version()], ["platform", platform.platform()]]
    rows += [[p, version(p)] for p in PACKAGES]
    inputs = [[k, v["path"], v["sha256"]] for k, v in prov.get("inputs", {}).items()]
    return ["## Environment", "", md_table(["tool / package", "version"], rows), "",
            md_table(["input", "path", "SHA-256"], inputs), ""]


def reproduce_lines(command: list[str] | None) -> list[str]:
    """Markdown section "Reproduce": the command line (shell-quoted)."""
    cmd = shlex.join(command) if command else "(run from Python: no command line)"
    return ["## Reproduce", "", "Re-running this command reproduces the report (and, with "
            "SOURCE_DATE_EPOCH set, its date):", "", f"`{cmd}`", ""]


def front_lines(asm, cond: dict, res: dict, flags: dict, conv: ConvergenceCase, prov: dict,
                command: list[str] | None, pipeline, fine_pipeline) -> list[str]:
    """The report's front sections in order: date, Margins, Inputs and their sources,
    Assumptions, Credibility, Environment, Reproduce. `pipeline`: the one of the results (the
    tolerance corners), `fine_pipeline`: its mesh at half the sizes (the headline errors)."""
    from studies.model.mesh_size import ORDER
    from studies.model.tolerances import has_tolerances
    from studies.usecases.tolerance_report import worst_case

    worst = worst_case(pipeline, cond) if has_tolerances(asm) else None

    err = headline_mesh_errors(cond, res, fine_pipeline, ORDER)
    n = len(np.asarray(res["preload_N"]))
    where = ("the conditions given" if "conditions" in prov.get("inputs", {}) else
             f"{asm.operating.T_min_C:g} .. {asm.operating.T_max_C:g} C, `[operating]`")
    path = prov.get("inputs", {}).get("assembly", {}).get("path")
    return ([f"Date: {report_date()}", ""]
            + margin_lines(margin_rows(asm, res, flags, err, cond), n, where)
            + pedigree_lines(asm, Path(path) if path else None)
            + assumption_lines(asm)
            + credibility_lines(conv, err, ORDER, tolerance=tolerance_lines(asm, res, worst))
            + environment_lines(prov) + reproduce_lines(command))
