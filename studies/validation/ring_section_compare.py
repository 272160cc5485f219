"""Rectangle vs grooved ring sections on the shipped stacks: how much cutting the
raceway groove and lands into the FE rings changes the fit pressures, the groove-centre shifts
and, through them, preload, contact angle and torque.

Per shipped assembly (studies/configs: seed000, seed001, seed003, template) the same conditions
are run twice through the public route (`simulate_table`, what `bearingfem simulate`
uses), once with `[mesh] ring_section = "rectangle"` (the effective sections of `[bearing]`) and
once with `"grooved"`; nothing else changes. Conditions: uniform temperature at `[operating]`
T_min_C, 20 C, the assembly temperature T_ref_C and T_max_C, at the assembly's default speed (`[lubrication] speed_rpm`, what
`simulate` takes without a speed column) and, when `[operating] speed_max_rpm` is higher, again
at that speed. The discretisation error of each mesh is measured the way `report` and
`verify --assembly` measure it (`studies.usecases.verify.mesh_convergence_case`: levels x2, x1, x0.5,
Richardson value, at T_min_C and T_max_C with the default speed), so a difference can be read
against it. Besides simulate's outputs, the preload change from T_ref_C (same speed) and, as a
diagnostic, the grooved results read with a free-radius circle fit (`radius_free`; the model
holds the groove radius at its thermal growth, docs/ring_sections.md explains why).

Run: `bearingfem study ring_sections --out DIR` or `python -m studies.validation.ring_section_compare
--out DIR`. Writes `ring_sections.csv` (one row per assembly, condition and quantity: rectangle,
grooved, absolute and relative difference), `mesh_error.csv` (per assembly and section) and
`report.md` / `report.html` (the tables).
"""
from __future__ import annotations

import argparse
import dataclasses
from datetime import date
from pathlib import Path

import numpy as np

from studies.model.columns import to_columns
from studies.model.config import CONFIG_DIR, load_assembly
from studies.model.pipeline import simulate_table
from studies.model.table import write_table

#: the shipped assemblies, short name -> file in studies/configs
ASSEMBLIES = {"seed000": "seed000_71807C_TC4.toml", "seed001": "seed001_flywheel_hybrid.toml",
              "seed003": "seed003_25TAC62B.toml", "template": "template.toml"}
SECTIONS = ("rectangle", "grooved")
#: quantities compared (simulate's output columns) and whether the FE gives them directly
FE_FITS = ("fit_pressure_inner_A_MPa", "fit_pressure_inner_B_MPa",
           "fit_pressure_outer_A_MPa", "fit_pressure_outer_B_MPa")
FE_SHIFTS = ("groove_shift_dr_A_um", "groove_shift_dz_A_um",
             "groove_shift_dr_B_um", "groove_shift_dz_B_um")
BEARING = ("preload_N", "contact_angle_deg", "torque_Nmm")
#: label of the grooved results read with a free-radius circle fit (`radius_free`)
FREE = "(grooved, radius fitted)"
#: a difference is called resolved when it exceeds this multiple of the discretisation error
RESOLVED_FACTOR = 2.0


def with_section(asm, section: str):
    """The assembly with `[mesh] ring_section` set to `section` (nothing else changed)."""
    return dataclasses.replace(asm, mesh=dataclasses.replace(asm.mesh, ring_section=section))


def conditions(asm) -> dict[str, np.ndarray]:
    """T_min, 20 C, the assembly temperature T_ref and T_max of `[operating]` at the default
    speed and, when `speed_max_rpm` exceeds it, at that speed too."""
    op, v0 = asm.operating, float(asm.lubrication.speed_rpm)
    temps = sorted({float(op.T_min_C), 20.0, float(asm.T_ref_C), float(op.T_max_C)})
    speeds = [v0] + ([op.speed_max_rpm] if op.max_speed_rpm(v0) > v0 else [])
    T = [t for _ in speeds for t in temps]
    v = [s for s in speeds for _ in temps]
    return {"T_ambient_C": np.array(T, float), "speed_rpm": np.array(v, float)}


def quantities(out: dict) -> list[str]:
    """The compared columns present in a simulate output (sleeve / cartridge fits when there)."""
    extra = [k for k in ("fit_pressure_sleeve_MPa", "fit_pressure_cartridge_MPa") if k in out]
    return [*FE_FITS, *extra, *FE_SHIFTS, *BEARING]


def mesh_error(asm) -> dict:
    """The achieved discretisation error of the assembly's mesh (report / verify --assembly)."""
    from studies.usecases.verify import mesh_convergence_case

    case = mesh_convergence_case(asm)
    a = case.assessment
    return {"error_max": float(a.error_max), "worst": max(a.errors, key=a.errors.get),
            "target_error": a.target_error, "within_target": a.within_target,
            "dofs": int(case.used.dofs)}


def _free_centres_mm(pl, inputs) -> tuple[np.ndarray, np.ndarray]:
    """(dr, dz) (2, n) in mm, inner minus outer per bearing like `FEState`, of the grooved
    pipeline `pl` read with the free-radius circle fit (`fem.post.circle_centre_weights`,
    free_radius=True) on each row's displacement field."""
    from fem.post import circle_centre_weights
    from studies.model.pipeline import RINGS

    basis = pl.model.sbasis
    centre = np.empty((inputs.n_rows, 4, 2))
    for i in range(inputs.n_rows):
        f = pl.field(inputs, row=i)
        ur_of, uz_of = basis.interpolator(f.u_mm[0::2]), basis.interpolator(f.u_mm[1::2])
        for k, ring in enumerate(RINGS):
            g = pl.section.groove_of(ring)
            X = np.array(g.points_rz_mm).T
            W, _ = circle_centre_weights(X, (g.r_mm, g.z_mm), free_radius=True)
            centre[i, k] = W @ np.column_stack([ur_of(X), uz_of(X)]).ravel()
    d = np.stack([centre[:, 0] - centre[:, 2], centre[:, 1] - centre[:, 3]])   # (2, n, 2)
    return d[..., 0], d[..., 1]


def radius_free(asm, cond: dict):
    """simulate's result (`SimulationResult`) for a grooved assembly with the groove-centre shifts read by the
    free-radius circle fit (centre and radius fitted) instead of the model's fit with the
    radius held at its thermal growth, at the rows and their assembly states, then the same
    bearing model (`FEOptions.centres`). The difference to `simulate` is the elastic change
    of the groove radius that a free fit turns into a centre shift (the bearing model receives
    the centre only). A diagnostic of this study."""
    from studies.model.pipeline import FEOptions, Pipeline, table_inputs

    pl = Pipeline.shared(asm)
    return pl.run(table_inputs(asm, cond), fe_options=FEOptions(centres=_free_centres_mm))


def _error_scale(q: str, out: dict, i: int) -> float | None:
    """The size the discretisation error is relative to (mesh_convergence_case): a fit
    pressure's own value, a shift component's bearing shift length; None for the bearing model."""
    if q.startswith("fit_pressure"):
        return abs(float(out[q][i]))
    if q.startswith("groove_shift"):
        J = q[-4]
        return float(np.hypot(out[f"groove_shift_dr_{J}_um"][i], out[f"groove_shift_dz_{J}_um"][i]))
    return None


def compare(name: str, asm, progress=print, errors: bool = True) -> tuple[list[dict], dict]:
    """Rows (one per condition and quantity) and {section: mesh error} of one assembly."""
    cond = conditions(asm)
    outs, err = {}, {}
    for s in SECTIONS:
        a = with_section(asm, s)
        progress(f"{name}: {s} sections, {cond['T_ambient_C'].size} conditions ...")
        outs[s] = to_columns(simulate_table(a, cond), flags=False)
        if errors:
            progress(f"{name}: {s} sections, mesh error (levels x2, x1, x0.5) ...")
            err[s] = mesh_error(a)
    progress(f"{name}: grooved, shifts read with a free-radius circle fit ...")
    free = to_columns(radius_free(with_section(asm, "grooved"), cond), flags=False)
    e_ref = max((e["error_max"] for e in err.values()), default=float("nan"))
    R, G = outs["rectangle"], outs["grooved"]
    T, v = cond["T_ambient_C"], cond["speed_rpm"]
    ref = [int(np.flatnonzero((T == asm.T_ref_C) & (v == v[i]))[0]) for i in range(T.size)]
    change = "preload change from T_ref_N"         # preload(T) - preload(T_ref), same speed
    R[change] = R["preload_N"] - R["preload_N"][ref]
    G[change] = G["preload_N"] - G["preload_N"][ref]
    free[change] = free["preload_N"] - free["preload_N"][ref]
    rows = []
    for i in range(T.size):
        for q in (quantities(R) + [change]
                  + [f"{q} {FREE}" for q in (*FE_SHIFTS, *BEARING, change)]):
            base = q.replace(f" {FREE}", "")
            r = float(R[base][i])
            g = float(free[base][i]) if base != q else float(G[q][i])
            d = g - r
            scale = _error_scale(base, R, i)
            scale = None if scale is None else max(scale, _error_scale(base, G, i))
            tol = (None if scale is None or not np.isfinite(e_ref) or r == g == 0.0
                   else RESOLVED_FACTOR * e_ref * scale)
            rows.append({"assembly": name, "T_C": float(cond["T_ambient_C"][i]),
                         "speed_rpm": float(cond["speed_rpm"][i]), "quantity": q,
                         "rectangle": r, "grooved": g, "difference": d,
                         "relative_percent": (100.0 * d / abs(r)) if abs(r) > 1e-12 else float("nan"),
                         "resolved": "" if tol is None else ("yes" if abs(d) > tol else "no")})
    return rows, err


def _cell(r: dict) -> str:
    if r["rectangle"] == r["grooved"] == 0.0:
        return "0 (open)" if r["quantity"].startswith("fit_pressure") else "0"
    rel = "" if not np.isfinite(r["relative_percent"]) else f"; {r['relative_percent']:+.2g} %"
    flag = " (within FE error)" if r["resolved"] == "no" else ""
    return f"{r['rectangle']:.4g} → {r['grooved']:.4g} ({r['difference']:+.3g}{rel}){flag}"


def markdown(rows: list[dict], errs: dict[str, dict]) -> list[str]:
    lines = [f"# Ring sections: rectangle vs grooved on the shipped stacks ({date.today().isoformat()})",
             "", "Each cell: rectangle → grooved (grooved − rectangle; relative to the rectangle). "
             "Uniform temperature (`T_ambient_C`), the speed as given. Groove shifts: inner minus "
             "outer groove-centre displacement, radial dr and axial dz, um. Fit pressures: mean "
             "pressure of each bearing's fit, MPa (0 = open). \"within FE error\": the "
             f"difference is below {RESOLVED_FACTOR:g}x the larger achieved discretisation error "
             "of the two meshes (relative to the pressure, or to the bearing's shift length).", ""]
    lines += ["## Achieved discretisation error", "",
              "| assembly | section | DOF | error achieved | worst quantity | target |",
              "|---|---|---|---|---|---|"]
    for name, e in errs.items():
        for s, v in e.items():
            lines.append(f"| {name} | {s} | {v['dofs']} | {100 * v['error_max']:.2g} % | "
                         f"{v['worst']} | {100 * v['target_error']:g} % |")
    lines.append("")
    for name in dict.fromkeys(r["assembly"] for r in rows):
        mine = [r for r in rows if r["assembly"] == name]
        conds = list(dict.fromkeys((r["T_C"], r["speed_rpm"]) for r in mine))
        qs = list(dict.fromkeys(r["quantity"] for r in mine))
        lines += [f"## {name}", "",
                  "| quantity | " + " | ".join(f"{T:g} C, {v:g} rpm" for T, v in conds) + " |",
                  "|---|" + "---|" * len(conds)]
        for q in qs:
            cells = [_cell(next(r for r in mine if r["quantity"] == q and (r["T_C"], r["speed_rpm"]) == c))
                     for c in conds]
            lines.append(f"| `{q}` | " + " | ".join(cells) + " |")
        lines.append("")
    return lines


def main(out_dir: Path, progress=print, assemblies=None, errors: bool = True) -> list[dict]:
    """Run the comparison for `assemblies` (short names of ASSEMBLIES; default all) into
    out_dir: ring_sections.csv, mesh_error.csv, report.md, report.html. Returns the rows."""
    from studies.usecases.report_tools import write_report_files

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows, errs = [], {}
    for name in assemblies or ASSEMBLIES:
        asm = load_assembly(CONFIG_DIR / ASSEMBLIES[name])
        r, e = compare(name, asm, progress, errors=errors)
        rows += r
        if e:
            errs[name] = e
    cols = ["assembly", "T_C", "speed_rpm", "quantity", "rectangle", "grooved", "difference",
            "relative_percent", "resolved"]
    # the one CSV dialect of bearingfem (studies.model.table.write_table, as `simulate`)
    write_table(out_dir / "ring_sections.csv", {c: np.array([r[c] for r in rows]) for c in cols})
    err_rows = [(name, s, v["dofs"], v["error_max"], v["worst"], v["target_error"], v["within_target"])
                for name, e in errs.items() for s, v in e.items()]
    write_table(out_dir / "mesh_error.csv", {
        c: np.array([row[i] for row in err_rows]) for i, c in enumerate(
            ["assembly", "section", "dofs", "error_max", "worst_quantity", "target_error",
             "within_target"])})
    write_report_files(out_dir, markdown(rows, errs), "Ring sections: rectangle vs grooved")
    return rows


def run(out: Path, progress=print) -> None:
    """`bearingfem study ring_sections --out DIR`."""
    main(out, progress)


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--assembly", action="append", choices=list(ASSEMBLIES),
                   help="only this assembly (may repeat; default all)")
    p.add_argument("--no-mesh-error", action="store_true", help="skip the mesh-error levels")
    args = p.parse_args()
    main(args.out, assemblies=args.assembly, errors=not args.no_mesh_error)
