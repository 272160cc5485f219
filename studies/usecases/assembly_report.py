"""`bearingfem report`: the engineer's report for any assembly.

Conditions: the given table, or a temperature sweep over the assembly's operating range
(`[operating]`, default -40..80 C) at its speed and preload. Everything comes from the pipeline
(the one route) and the checks `simulate` applies. Contents: what made it (tool version, input
hashes), the input echo (geometry, materials with E, nu, CTE and their sources, fits, preload,
lubrication, limits), the results per operating point with the Lamé values beside the FE fit
pressures, plots vs temperature, the safety table, field images and VTU at the coldest, reference
and hottest temperature, the speed effects of the rotor's centrifugal growth (fit-loosening speed
of each inner fit, fit pressure and preload at rest and at the highest speed), and the
discretisation error of this assembly's own mesh (observed order
and GCI over three mesh levels, Roache 1998; the target error its sizes were chosen for and the
error achieved). Written as `report.md` and a self-contained
`report.html` (images embedded), with the CSV tables.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from studies.model.checks import assembly_checks, plausibility_warnings
from studies.model.columns import to_columns
from studies.model.pipeline import SPEED_SEARCH_MAX_RPM, Pipeline, simulate_table, table_inputs
from studies.model.table import write_table
from analytic import lame
from fem.fields import COLOUR_PERCENTILE
from analytic.bearing.land import land_diameters_mm
from studies.model.tolerances import fits_of, has_tolerances
from studies.usecases import fit_naming, report_margins, report_pdf
from studies.usecases import sensitivity as sensitivity_run
from studies.usecases.report_tools import (condition_text, field_images, nice_step, line_plot, md_table, safety_section,
                                       significant, write_report_files)

N_SWEEP = 25            # about this many points in the default temperature sweep
RESULT_ROWS = 12        # rows of the result table in the text (the CSV has them all)


def default_conditions(asm) -> dict[str, np.ndarray]:
    """A temperature sweep over the operating range at the assembly's speed and preload."""
    op = asm.operating
    step = nice_step(op.T_max_C - op.T_min_C, N_SWEEP)
    grid = step * np.arange(np.ceil(op.T_min_C / step), np.floor(op.T_max_C / step) + 1)
    T = np.unique(np.concatenate([[op.T_min_C, op.T_max_C, asm.T_ref_C], grid]))
    T = T[(T >= op.T_min_C) & (T <= op.T_max_C)]
    return {"T_ambient_C": T}


@dataclass(frozen=True)
class ReportRun:
    """What `report` wrote besides the files: the warning lines (also in the report; an
    assumption whose alternative turns a PASS into a FAIL is one), results.csv's columns (the
    conditions, then the output columns of `simulate`) and the assumptions that decide the
    answer (`sensitivity.Sensitivity`; sensitivity.csv with --sensitivity)."""
    warnings: list
    columns: dict
    sensitivity: "sensitivity_run.Sensitivity | None" = None

    def to_frame(self):
        """results.csv's columns as a `pandas.DataFrame` (units in the names)."""
        import pandas as pd

        return pd.DataFrame(self.columns)


def run(asm, conditions: dict | None, out: Path, provenance: dict, progress=print,
        mesh_factor: float = 1.0, rig_sections: list[str] | None = None,
        field_temperatures_C: tuple[float, ...] | None = None, pdf: bool = False,
        command: list[str] | None = None, sensitivity: bool = False) -> list[str]:
    """Write the report into `out`; returns the warning lines (also in the report) and the
    results table (`ReportRun`).

    rig_sections: markdown lines a study of a particular rig adds (its own questions, the
    published measurement beside the model), placed after the safety table.
    field_temperatures_C: where to draw field images (default: coldest, reference, hottest).
    pdf: also report.pdf (studies/usecases/report_pdf.py); command: the command line that made it
    (the "Reproduce" section). The front sections (margins, pedigree, assumptions, credibility,
    environment, command): studies/usecases/report_margins.py. After the margins, "Assumptions
    that decide the answer" (studies/usecases/sensitivity.py): the modelling choices at their
    defaults; `sensitivity`: also the ring section and the `[assume]`-tagged numbers, and
    sensitivity.csv."""
    from studies.usecases.verify import mesh_convergence_case

    cond = dict(conditions) if conditions is not None else default_conditions(asm)
    cond = {k: np.asarray(v, float) for k, v in cond.items() if not k.startswith("_")}
    pl = Pipeline.shared(asm, mesh_factor=mesh_factor, progress=progress)
    progress(f"report: {len(next(iter(cond.values())))} operating points ...")
    result = simulate_table(asm, cond, pipeline=pl)
    res = to_columns(result)            # the report's tables and plots read columns by name
    violations = result.checks.violations()
    warnings = plausibility_warnings(asm, cond, res)
    n = result.n_rows
    write_table(out / "results.csv", {**cond, **res}, provenance=provenance)
    x, xlabel = _x_axis(cond, n)
    plots = _plots(out, asm, x, xlabel, res)
    progress("report: field images ...")
    design = None if field_temperatures_C else design_rows(cond, res)
    if design is None:
        temps = field_temperatures_C or sorted({asm.operating.T_min_C, asm.T_ref_C,
                                                asm.operating.T_max_C})
        images = {f"{T:g} C": field_images(out, pl, {"T_ambient_C": np.array([T])},
                                           f"field_{T:+.0f}C", f"{asm.name} at {T:g} C")
                  for T in temps}
    else:
        images = {condition_text(cond, i): field_images(
                      out, pl, {k: v[i:i + 1] for k, v in cond.items()}, f"field_row{i + 1}",
                      f"{asm.name}, row {i + 1}") for i in design}
    progress("report: speed effects (fit-loosening speeds) ...")
    speed = speed_lines(asm, pl, None if design is None else
                        {k: v[design] for k, v in cond.items()},
                        None if design is None else
                        [condition_text(cond, i) for i in design])
    progress("report: discretisation error of this mesh (three levels) ...")
    conv = mesh_convergence_case(asm, factors=tuple(mesh_factor * f for f in (2.0, 1.0, 0.5)),
                                 used=1)
    # the columns view holds the flag and margin columns the margin table reads
    front = report_margins.front_lines(asm, cond, res, res, conv, provenance, command, pl,
                                       Pipeline.shared(asm, mesh_factor=0.5 * mesh_factor))
    path = provenance.get("inputs", {}).get("assembly", {}).get("path")
    sens = sensitivity_run.run(asm, cond, report_margins.margin_rows(asm, res, res, {}, cond),
                               Path(path) if path else None, mesh_factor, sensitivity, progress)
    if sensitivity:
        sensitivity_run.write_csv(out / "sensitivity.csv", sens, provenance)
    k = next(i for i, line in enumerate(front) if line == "## Inputs and their sources")
    front = front[:k] + sensitivity_run.section_lines(sens) + front[k:]
    naming = fit_naming.report_lines(asm, out)      # which layer is which (with a layer only)
    lines = _text(asm, provenance, cond, res, result, violations, warnings, plots, images, conv, pl, x,
                  xlabel, naming + speed + (rig_sections or []))
    k = next(i for i, line in enumerate(lines) if line.startswith("## "))
    lines = lines[:k] + front + lines[k:]           # after the title and the summary
    write_report_files(out, lines, asm.name)
    if pdf:
        report_pdf.write_pdf(out, lines, f"Assembly report: {asm.name}")
    flips = [f"{r.assumption} -> {r.alternative} turns {r.item} from {r.status} to "
             f"{r.status_alternative}" for r in sens.flips]
    return ReportRun(warnings + [v.summary(n, cond) for v in violations] + flips,
                     {**cond, **res}, sens)


def design_rows(cond: dict, res: dict) -> list[int] | None:
    """The operating points that drive the design when the conditions carry more than a uniform
    temperature (a part's own T_<part>_C column: a gradient): the rows of the lowest and the
    highest preload and of the highest contact pressure (0-based, sorted, once each). None for a
    uniform-temperature sweep (the field images stay at the coldest, reference and hottest
    temperature)."""
    from studies.model.inputs import PART_COLUMNS

    if not any(c in cond for c in PART_COLUMNS):
        return None
    p = np.asarray(res["preload_N"], float)
    q = np.asarray(res["max_contact_pressure_MPa"], float)
    return sorted({int(np.argmin(p)), int(np.argmax(p)), int(np.argmax(q))})


def speed_lines(asm, pl: Pipeline, rows: dict | None = None,
                labels: list[str] | None = None) -> list[str]:
    """Markdown section "Speed": at the coldest, reference and hottest temperature (nominal fits)
    or, given `rows` (conditions columns of the operating points that drive the design,
    `design_rows`, each labelled by `labels`), at those points with their part temperatures, the
    speed at which each inner fit opens (`Pipeline.fit_open_speed_rpm`) and the inner fit
    pressure (FE, and the two-cylinder rotating Lamé value beside it), the preload and the radial
    groove-centre shift of bearing A at rest and at the highest speed (`[operating]
    speed_max_rpm`, else `[lubrication] speed_rpm`)."""
    op = asm.operating
    n_max = op.max_speed_rpm(asm.lubrication.speed_rpm)
    if rows is None:
        T = np.array(sorted({op.T_min_C, asm.T_ref_C, op.T_max_C}), float)
        rows, labels = {"T_ambient_C": T}, [f"{t:g}" for t in T]
    m = len(labels)
    pairs = {k: np.repeat(np.asarray(v, float), 2) for k, v in rows.items() if k != "speed_rpm"}
    inp = table_inputs(asm, {**pairs, "speed_rpm": np.tile([0.0, n_max], m)})
    res = pl.run(inp)
    r = to_columns(res, flags=False)
    n_open = pl.fit_open_speed_rpm(inp.take(np.arange(0, 2 * m, 2)))
    ms, mr = pl.materials["shaft"], pl.materials["inner_ring_A"]
    n_lame = 60.0 / (2.0 * np.pi) * lame.fit_open_speed_rad_s(
        asm.shaft.bore_diameter_mm / 2, asm.shaft.seat_diameter_mm / 2,
        asm.bearing.inner_ring_outer_diameter_mm / 2, ms.E_MPa, ms.nu, mr.E_MPa, mr.nu,
        res.fe.interference_um[0::2, 0], ms.density_N_s2_mm4, mr.density_N_s2_mm4)

    def rpm(v):
        return f"> {SPEED_SEARCH_MAX_RPM:.0e}" if np.isinf(v) else f"{v:.0f}"

    rows = []
    for i, label in enumerate(labels):
        a, b = 2 * i, 2 * i + 1
        rows.append([label] + [rpm(v) for v in n_open.speed_rpm[i]] + [rpm(n_lame[i])]
                    + [f"{r['fit_pressure_inner_MPa'][a]:.4g}", f"{r['fit_pressure_inner_MPa'][b]:.4g}",
                       f"{r['fit_pressure_inner_lame_MPa'][b]:.4g}",
                       f"{r['preload_N'][a]:.4g}", f"{r['preload_N'][b]:.4g}",
                       f"{r['groove_shift_dr_A_um'][b] - r['groove_shift_dr_A_um'][a]:+.3g}"])
    head = ([("T (C)" if labels and labels[0][0] != "r" else "operating point")]
            + [f"{k.replace('fit_', '')} opens at (rpm)" for k in n_open.names]
            + ["Lamé opens at (rpm)"]
            + ["inner fit p at rest (MPa)", f"at {n_max:g} rpm (MPa)", "Lamé at speed (MPa)",
               "preload at rest (N)", f"at {n_max:g} rpm (N)", "dr_A change (um)"])
    return ["## Speed", "",
            "### The rotor's centrifugal growth", "",
            "The rotor (shaft, inner rings, inner spacer, nut) spins; its centrifugal body force "
            "rho omega^2 r expands the inner rings' bores more than the shaft's seat, so the inner "
            "fits loosen with speed and open at the fit-loosening speed (the whole fit open, mean "
            "pressure 0; searched up to "
            f"{SPEED_SEARCH_MAX_RPM:.0e} rpm). The stator does not spin: the outer fits do not "
            "change with speed. Nominal fits; the assembly state is at rest. The balls' own "
            "centrifugal force is not part of this FE effect. Lamé: shaft and inner ring as two "
            "spinning cylinders in plane stress (analytic/lame.py, Timoshenko & Goodier §32).", "",
            md_table(head, rows), ""] + ball_speed_lines(asm, pl, n_max)


def ball_speed_lines(asm, pl: Pipeline, n_max: float) -> list[str]:
    """Markdown subsection "The balls at speed": at the reference temperature, at rest and at
    n_max, the pair with quasi-static balls against quasi-dynamic balls (centrifugal force and
    gyroscopic moment; analytic/bearing/dynamic.py, raceway control as configured): preload,
    inner and outer contact angle and ball load of bearing A, torque."""
    if n_max <= 0:
        return []
    inp = table_inputs(asm, {"T_ambient_C": np.full(2, asm.T_ref_C),
                             "speed_rpm": np.array([0.0, n_max])})
    runs = {m: to_columns(pl.run(inp, ball_model=m), flags=False)
            for m in ("static", "quasi_dynamic")}
    cols = [("preload_N", "preload (N)", ".4g"), ("contact_angle_A_deg", "A inner angle (deg)", ".3f"),
            ("contact_angle_outer_A_deg", "A outer angle (deg)", ".3f"),
            ("ball_load_A_N", "A inner ball load (N)", ".4g"),
            ("ball_load_outer_A_N", "A outer ball load (N)", ".4g"),
            ("centrifugal_force_N", "centrifugal force per ball (N)", ".3g"),
            ("torque_Nmm", "torque (N mm)", ".4g")]
    rows = [["at rest"] + [format(runs["static"][k][0], f) for k, _, f in cols]]
    for m, label in (("static", "quasi-static balls"), ("quasi_dynamic", "quasi-dynamic balls")):
        rows.append([f"{n_max:g} rpm, {label}"] + [format(runs[m][k][1], f) for k, _, f in cols])
    used = {"static": "quasi-static", "quasi_dynamic": "quasi-dynamic"}[asm.operating.ball_model]
    return ["### The balls at speed", "",
            f"At {asm.T_ref_C:g} C. Each ball's centrifugal force m omega_c^2 dm/2 presses it "
            "onto the outer raceway and its gyroscopic moment is taken by friction at the "
            f"controlling raceway ({asm.operating.raceway_control} control): the outer contact "
            "angle falls, the inner one rises, and the outer contact carries more load than the "
            "inner one (Jones 1960; Harris & Kotzalas Vol. 2 ch. 3; analytic/bearing/dynamic.py). "
            f"This assembly's results use {used} balls (`[operating] ball_model`).", "",
            md_table(["state"] + [h for _, h, _ in cols], rows), ""]


def _x_axis(cond, n):
    for key, label in (("T_ambient_C", "ambient temperature (C)"), ("time_s", "time (s)"),
                       ("preload_assembled_N", "assembled preload (N)"), ("speed_rpm", "speed (rpm)")):
        if key in cond and np.ptp(cond[key]) > 0:
            return cond[key], label
    return np.arange(1, n + 1, dtype=float), "operating point"


def _plots(out: Path, asm, x, xlabel, r) -> dict[str, Path]:
    p = {}
    fits = fits_of(asm)               # every fit present: inner, outer, sleeve, cartridge
    p["fits"] = line_plot(out / "fits.png", x, {
        f"{f}: free interference (um)": r[f"interference_{f}_um"] for f in fits}, xlabel,
        "diametral interference (um; < 0 clearance)", "Fits at temperature")
    p["fit_pressure"] = line_plot(out / "fit_pressure.png", x, {
        label: v for f in fits for label, v in ((f"{f} fit, FE", r[f"fit_pressure_{f}_MPa"]),
                                                (f"{f} fit, Lamé (plane stress)",
                                                 r[f"fit_pressure_{f}_lame_MPa"]))}, xlabel,
        "mean fit pressure (MPa)", "Fit pressures: FE and the closed form beside it")
    p["groove_shifts"] = line_plot(out / "groove_shifts.png", x, {
        k: r[f"groove_shift_{k}_um"] for k in ("dr_A", "dz_A", "dr_B", "dz_B")}, xlabel,
        "inner minus outer groove centre (um)", "Groove-centre shifts from the FE")
    p["preload"] = line_plot(out / "preload.png", x, {
        "preload of the pair": r["preload_N"], "axial force A": r["axial_force_A_N"],
        "axial force B": r["axial_force_B_N"]}, xlabel, "N", "Preload")
    p["contact_angle"] = line_plot(out / "contact_angle.png", x, {
        "A": r["contact_angle_A_deg"], "B": r["contact_angle_B_deg"]}, xlabel,
        "contact angle (deg)", "Contact angle")
    limit = next(c.allowable for c in assembly_checks(asm) if c.name == "max_contact_pressure_MPa")
    p["contact_pressure"] = line_plot(out / "contact_pressure.png", x, {
        "max Hertz pressure": r["max_contact_pressure_MPa"],
        f"limit {limit:g} MPa": np.full(len(x), limit)}, xlabel, "MPa",
        "Maximum contact pressure and its limit")
    p["stiffness"] = line_plot(out / "stiffness.png", x, {
        "axial stiffness of the pair": r["axial_stiffness_N_per_um"]}, xlabel, "N/um",
        "Axial stiffness")
    parts = {k: r[k] for k in ("torque_Nmm", "torque_hysteresis_Nmm", "torque_differential_Nmm",
                               "torque_spin_Nmm", "torque_load_Nmm", "torque_viscous_Nmm") if k in r}
    p["torque"] = line_plot(out / "torque.png", x, {k.replace("torque_", "").replace("_Nmm", "")
                                                   or "total": v for k, v in parts.items()},
                            xlabel, "friction torque of the pair (N mm)", "Torque by component")
    return p


def _materials(asm) -> list[list]:
    rows, seen = [], set()
    for part in ("shaft", "housing", "nut", "cover", "inner_spacer", "outer_spacer",
                 "inner_ring", "ball", *(n for n, _ in asm.layers())):
        m = asm.material(part)
        key = (part if part not in ("inner_ring",) else "rings", m.name)
        if key in seen:
            continue
        seen.add(key)
        rows.append([key[0], m.name, m.E_MPa, m.nu, m.alpha_per_K * 1e6, m.source])
    return rows


def _echo(asm) -> list[str]:
    """Every input table of the assembly, key = value, as given."""
    from dataclasses import fields

    out = []
    for name in ("shaft", "housing", "nut", "cover", "inner_spacer", "outer_spacer", "bearing",
                 "fits", "preload", "lubrication", "limits", "mesh", "operating",
                 *(n for n, _ in asm.layers())):
        sec = getattr(asm, name)
        out.append([f"[{name}]", ", ".join(f"{f.name} = {getattr(sec, f.name)}" for f in fields(sec))])
    return out


def _text(asm, prov, cond, r, result, violations, warnings, plots, images, conv, pl, x, xlabel,
          rig_sections):
    n = len(r["preload_N"])
    idx = np.unique(np.linspace(0, n - 1, min(n, RESULT_ROWS)).round().astype(int))
    inputs = ", ".join(f"{k} `{v['path']}` (sha256 {v['sha256'][:12]}...)"
                       for k, v in prov["inputs"].items())
    lines = [f"# Assembly report: {asm.name}", "",
             f"bearingfem {prov['version']}; {inputs}. {asm.source}", "",
             f"{asm.bearing.designation} pair, {asm.arrangement}, {asm.preload.kind} preload "
             f"{asm.preload.assembled_N:g} N at {asm.T_ref_C:g} C; FE model {pl.ndofs} DOF "
             "(axisymmetric, P2, exact fit contact); bearing: exact Hertz, pair equilibrium.", ""]
    if has_tolerances(asm):
        mi, mo = asm.mean_fits_um()
        lines += [f"Fits: the mean assembly of the [fits] tolerances, {mi:+.2f} um inner and "
                  f"{mo:+.2f} um outer (every deviation at the middle of its band); "
                  "`bearingfem tolerance` gives their scatter.", ""]
    if warnings or violations:
        lines += ["## Warnings", ""] + [f"- {w}" for w in warnings] + \
                 [f"- {v.summary(n, cond)}" for v in violations] + [""]
    lines += ["## Inputs", "", md_table(["table", "values"], _echo(asm)), "",
              md_table(["part", "material", "E (MPa)", "nu", "CTE (1e-6/K)", "source"],
                       _materials(asm)), ""]
    cols = ["preload_N", "contact_angle_deg", "torque_Nmm", "max_contact_pressure_MPa",
            "interference_inner_um", "fit_pressure_inner_MPa", "fit_pressure_inner_lame_MPa",
            "interference_outer_um", "fit_pressure_outer_MPa", "fit_pressure_outer_lame_MPa",
            *(c for n, _ in asm.layers() for c in (f"interference_{n}_um", f"fit_pressure_{n}_MPa",
                                                   f"fit_pressure_{n}_lame_MPa")),
            "axial_stiffness_N_per_um"]
    lines += ["## Results", "",
              f"{n} operating points (all of them in `results.csv`, with every output, flag and "
              "margin column; `results.csv.json` says what made it). FE fit pressures with the "
              "two-cylinder Lamé value beside them (plane stress; a short ring tied to its "
              "neighbours need not equal it)"
              + ("" if not asm.layers() else
                 "; the outer, sleeve and cartridge fits with the multi-layer Lamé value of the "
                 "concentric outer ring / layers / housing (analytic/lame.py)") + ".", "",
              md_table([xlabel] + cols, [[float(x[i])] + [significant(r[c], i) for c in cols]
                                         for i in idx]),
              ""]
    for key in ("fits", "fit_pressure", "groove_shifts", "preload", "contact_angle",
                "contact_pressure", "stiffness", "torque"):
        lines += [f"![{key}]({plots[key].name})", ""]
    lines += [safety_section(asm, result, title="all operating points", conditions=cond)]
    d_land = land_diameters_mm(asm.bearing, asm.materials)
    lines += [f"Contact ellipse and groove edge: land diameters {d_land[0]:.3f} / {d_land[1]:.3f} mm "
              f"(inner / outer; {d_land[2]}); smallest angle between the ellipse's edge and the "
              f"land {np.min(r['land_margin_inner_deg']):.1f} deg (inner), "
              f"{np.min(r['land_margin_outer_deg']):.1f} deg (outer); negative would mean the "
              "ellipse is truncated (analytic/bearing/land.py).", ""]
    lines += rig_sections
    where = ("at the coldest, reference and hottest temperature" if all(
        h.endswith(" C") for h in images) else "at the operating points that drive the design "
        "(lowest and highest preload, highest contact pressure), each with its own part "
        "temperatures and speed as given")
    lines += ["## Field images", "",
              f"Displacement (deformed shape, exaggeration in the title), hoop and von Mises stress "
              f"{where}, nominal fits; the VTU files open in ParaView. The stress colour bars end "
              f"at the {COLOUR_PERCENTILE:g}th percentile of the element values weighted by "
              "their area (the bar states the maximum): the elastic stress at a re-entrant corner is singular and would otherwise "
              "set the scale and leave the section one colour.", ""]
    for head, paths in images.items():
        lines += [f"### {head}", "", " ".join(f"![{p.stem}]({p.name})" for p in paths), ""]
    from studies.usecases.verify import discretisation_lines

    lines += ["## Discretisation error of this mesh", ""] + discretisation_lines(conv)
    return lines
