"""Study `heatup`: seed 003's ball-screw support (25TAC62B pair, back-to-back, 1500 N preload,
25 C ambient) heating up at 1000 and 1500 rpm, through `simulate`'s transient route
(studies/model/transient_route.py): the conduction FE of the stack reduced once, the loop
temperature -> fits and groove shifts -> pair -> torque -> heat closed as the run goes.

Set-up (seed 003, section 4: NSK 25TAC62B pair back-to-back, axial preload 1500 N, ambient 25 C,
1000 and 1500 r/min; its 50 N radial load is left out here: the pair under pure preload). Films:
housing and cover 15 W/m2K (natural convection + radiation), shaft and nut 60 W/m2K (rotating
shaft in air), the rest of the stack (bearing cavity, spacers) 30 W/m2K: the assumptions of the
seed 003 study and of `bearingfem bench --transient`. Fit conductances from the fit pressures
(Yovanovich). Ball-raceway contacts: moving-source constriction on both sides at the rolling
speed with the EHL film (oil at ambient-pressure conductivity) in series, Blok's partition of each
contact's heat (`analytic.heat.rolling_contact_conductance`), refreshed from the contact state.
Three hours, as the seed's test.

Checked against the seed's qualitative findings (its section 3, fig. 9, at 1500 r/min, and its
conclusions 1 and 2): the balls are the hottest part, the inner ring warmer than the outer; the
temperature difference between the rings and the balls is below 4 K; the heat falls as the oil
thins and levels off (the total heat of the last half hour changes by less than 2 %). Each is
stated as found; `findings` returns them for the test.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from studies.model.config import Thermal, load_shipped
from studies.model.pipeline import Pipeline
from studies.model.table import write_table
from studies.model.transient_route import ball_contacts, run_transient, thermal_model
from studies.runs.report_tools import line_plot, md_table

SPEEDS_RPM = (1000.0, 1500.0)
PRELOAD_N = 1500.0
AMBIENT_C = 25.0
DURATION_S = 3 * 3600.0
ROW_S = 60.0
#: instants of the field images (s)
INSTANTS_S = (300.0, 1800.0, DURATION_S)
FILMS = (("housing_outer", 15.0), ("free_housing", 15.0), ("free_cover", 15.0),
         ("shaft_end", 60.0), ("free_shaft", 60.0), ("free_nut", 60.0), ("*", 30.0))
PARTS = ("ball", "inner_ring", "outer_ring", "shaft", "spacer", "housing")


def assembly():
    """Seed 003's assembly in transient mode with the study's films."""
    return replace(load_shipped("seed003"), thermal=Thermal(mode="transient", films=FILMS))


@dataclass(frozen=True)
class Findings:
    """The seed's qualitative findings as this run gives them (at the end of the run)."""
    speed_rpm: float
    T_end_C: dict
    ball_hottest: bool
    ring_ball_dT_K: float           # largest |T_ball - T_ring| of the two rings
    inner_outer_dT_K: float         # T_inner_ring - T_outer_ring
    inner_outer_dT_max_K: float     # its largest value over the run
    heat_change_last_30min: float   # relative change of the total heat over the last 30 min
    heat_ratio_end_to_5min: float   # total heat at the end / at 5 minutes
    end_rate_K_per_h: float         # largest |dT/dt| of a part over the last 10 minutes


def heat_up(pl: Pipeline, speed_rpm: float, duration_s: float = DURATION_S,
            row_s: float = ROW_S, progress=None):
    """One heat-up: (rows' outputs, the `TransientRun`)."""
    t = np.arange(0.0, duration_s + 0.5 * row_s, row_s)
    n = t.size
    cols = {"time_s": t, "T_ambient_C": np.full(n, AMBIENT_C), "speed_rpm": np.full(n, speed_rpm),
            "preload_assembled_N": np.full(n, PRELOAD_N)}
    run = run_transient(pl, cols, progress)
    return {**cols, **run.columns()}, run


def findings(out: dict, speed_rpm: float) -> Findings:
    t = out["time_s"]
    T = {p: float(out[f"T_{p}_C"][-1]) for p in PARTS if f"T_{p}_C" in out}
    others = [v for p, v in T.items() if p != "ball"]
    heat = out["heat_bearing_W"]
    i30 = int(np.searchsorted(t, t[-1] - 1800.0))
    i10 = int(np.searchsorted(t, t[-1] - 600.0))
    rate = max(abs(out[f"T_{p}_C"][-1] - out[f"T_{p}_C"][i10]) / (t[-1] - t[i10]) * 3600.0
               for p in T)
    io = out["T_inner_ring_C"] - out["T_outer_ring_C"]
    i5 = int(np.searchsorted(t, t[0] + 300.0))
    return Findings(speed_rpm, T, T["ball"] > max(others),
                    max(abs(T["ball"] - T["inner_ring"]), abs(T["ball"] - T["outer_ring"])),
                    T["inner_ring"] - T["outer_ring"], float(np.max(io)),
                    float(abs(heat[-1] - heat[i30]) / heat[-1]), float(heat[-1] / heat[i5]),
                    float(rate))


def field_images(out_dir: Path, pl: Pipeline, run, instants_s, speed_rpm: float,
                 preload_N: float, tag: str, label=lambda t_s: f"t = {t_s / 60:.0f} min"
                 ) -> list[Path]:
    """Temperature (and displacement) images of a `TransientRun` at the given instants (s): the
    reduced field at the grid point nearest each instant, its displacement from a direct FE solve
    of that field (`Pipeline.fe_field`) at the speed (rpm) and assembled preload (N) given; files
    field_<tag>_<instant>_*.png. Used by the heatup and tvac studies."""
    from fem.fields import render_fields
    from studies.model.inputs import baseline_inputs

    tm = thermal_model(pl)
    m, a = pl.model, pl.asm
    paths = []
    for ts in instants_s:
        k = int(np.argmin(np.abs(run.grid_s - ts)))
        T = tm.rc.field(run.q[k])
        inp = baseline_inputs({"speed_rpm": np.array([speed_rpm])}, 1, a.T_ref_C, preload_N,
                              speed_rpm)
        _, u = pl.fe_field(tm.tc.theta_field(T, a.T_ref_C), inp)
        paths += render_fields(out_dir, f"field_{tag}_{ts / 60:.0f}min", m, u, {},
                               f"{tag}, {label(run.grid_s[k])}",
                               T_vertex_C=T[m.sbasis.nodal_dofs[0]])
    return paths


def ball_contact_lines(pl: Pipeline, rows: dict, speed_rpm: float) -> list[str]:
    """One line per raceway: the ball-raceway resistances of one contact and the set's
    conductance at the last row's state (`transient_route.ball_contacts`)."""
    from studies.model.inputs import baseline_inputs

    T_oil = float(np.mean([rows[f"T_{p}_C"][-1] for p in ("inner_ring", "outer_ring", "ball")]))
    inp = baseline_inputs({"speed_rpm": np.array([speed_rpm])}, 1, pl.asm.T_ref_C, PRELOAD_N,
                          speed_rpm)
    pair = pl.run(inp, remember=False).pair
    out = []
    for side, c in zip(("inner", "outer"), ball_contacts(pl, pair, speed_rpm, T_oil)):
        out.append(f"- {speed_rpm:.0f} rpm, {side} raceway: per contact ball side "
                   f"{c.R_ball_K_W:.2f} K/W, EHL film {c.R_film_K_W:.2f} K/W, ring side "
                   f"{c.R_ring_K_W:.2f} K/W; ball set to raceway {c.G_W_K:.3f} W/K per bearing, "
                   f"ring share of the contact heat {c.ring_share:.3f}")
    return out


def run(out: Path, progress=print, mesh_factor: float = 1.0, duration_s: float = DURATION_S,
        images: bool = True) -> dict[float, Findings]:
    """Write the study's tables, plots, field images and report into `out`; mesh_factor > 1
    coarsens the FE mesh (smoke tests). Returns the findings per speed."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    pl = Pipeline.shared(assembly(), mesh_factor=mesh_factor, progress=progress)
    res, found, imgs = {}, {}, {}
    for n in SPEEDS_RPM:
        progress(f"heatup: {n:.0f} rpm, {duration_s / 3600:g} h ...")
        rows, r = heat_up(pl, n, duration_s, progress=progress)
        res[n] = rows
        found[n] = findings(rows, n)
        keep = ["time_s", *(f"T_{p}_C" for p in PARTS), "T_max_C", "T_min_C", "preload_N",
                "torque_Nmm", "heat_bearing_W", "contact_angle_deg", "fit_pressure_inner_MPa",
                "fit_pressure_outer_MPa", "reduction_error_est"]
        write_table(out / f"heatup_{n:.0f}rpm.csv", {k: rows[k] for k in keep if k in rows})
        tmin = rows["time_s"] / 60.0
        line_plot(out / f"temperatures_{n:.0f}rpm.png", tmin,
                  {p: rows[f"T_{p}_C"] for p in PARTS if f"T_{p}_C" in rows}, "time (min)",
                  "temperature (C)", f"Transient FE (reduced), {n:.0f} rpm, {PRELOAD_N:g} N")
        if images:
            imgs[n] = field_images(out, pl, r, INSTANTS_S, n, PRELOAD_N, f"{n:.0f}rpm")
    tm = thermal_model(pl)
    t = {n: res[n]["time_s"] / 60.0 for n in SPEEDS_RPM}
    line_plot(out / "preload.png", t[SPEEDS_RPM[0]],
              {f"{n:.0f} rpm": (t[n], res[n]["preload_N"]) for n in SPEEDS_RPM}, "time (min)",
              "preload (N)", "Preload against time")
    line_plot(out / "torque.png", t[SPEEDS_RPM[0]],
              {f"{n:.0f} rpm": (t[n], res[n]["torque_Nmm"]) for n in SPEEDS_RPM}, "time (min)",
              "friction torque (N mm)", "Torque against time")
    line_plot(out / "heat.png", t[SPEEDS_RPM[0]],
              {f"{n:.0f} rpm": (t[n], res[n]["heat_bearing_W"]) for n in SPEEDS_RPM}, "time (min)",
              "heat of the pair (W)", "Friction heat against time")
    contacts = [line for n in SPEEDS_RPM for line in ball_contact_lines(pl, res[n], n)]
    _report(out, found, res, tm.rc.m, imgs, contacts)
    return found


def _report(out: Path, found: dict, res: dict, modes: int, imgs: dict, contacts: list) -> None:
    rows = []
    for n, f in found.items():
        r = res[n]
        rows.append([f"{n:.0f}", *(f"{f.T_end_C[p]:.2f}" for p in PARTS if p in f.T_end_C),
                     f"{r['preload_N'][-1]:.0f}", f"{r['torque_Nmm'][-1]:.1f}",
                     f"{r['heat_bearing_W'][-1]:.2f}", f"{f.end_rate_K_per_h:.2f}"])
    head = ["rpm", *(f"T_{p} (C)" for p in PARTS if p in found[SPEEDS_RPM[0]].T_end_C),
            "preload (N)", "torque (N mm)", "heat (W)", "dT/dt at the end (K/h)"]
    checks = []
    for n, f in found.items():
        checks += [
            f"- {n:.0f} rpm: balls the hottest part: {'yes' if f.ball_hottest else 'NO'}; "
            f"largest ring-to-ball difference {f.ring_ball_dT_K:.2f} K (seed, at 1500 rpm: below "
            f"4 K: {'yes' if f.ring_ball_dT_K < 4 else 'NO'}); inner minus outer ring "
            f"{f.inner_outer_dT_K:+.2f} K (inner warmer: {'yes' if f.inner_outer_dT_K > 0 else 'NO'}"
            f"; largest over the run {f.inner_outer_dT_max_K:+.2f} K); heat at the end "
            f"{100 * f.heat_ratio_end_to_5min:.1f} % of that at 5 min (falls: "
            f"{'yes' if f.heat_ratio_end_to_5min < 1 else 'NO'}), change over the last 30 min "
            f"{100 * f.heat_change_last_30min:.2f} % (levelled off below 2 %: "
            f"{'yes' if f.heat_change_last_30min < 0.02 else 'NO'})"]
    err = max(float(np.max(r["reduction_error_est"])) for r in res.values())
    lines = ["# Heat-up of seed 003's ball-screw support (transient conduction FE)", "",
             __doc__.split("\n\n")[1].replace("\n", " "), "",
             f"Reduced model: {modes} thermal modes; largest estimated relative preload error of "
             f"the reduction over the runs {err:.1e} (`reduction_error_est`; against the full FE: "
             "`bearingfem bench --transient`).", "",
             "## Equilibrium (the state at the end of the run)", "",
             md_table(head, rows), "",
             "## The seed's findings", "", *checks, "",
             "## Ball-raceway contacts at the end of the run", "",
             "The film term dominates: with the oil's ambient-pressure conductivity (0.14 W/(m K)) "
             "it is an upper bound (under the Hertz pressure the conductivity is 1.5-2.5 x "
             "higher); without a film (boundary lubrication) the conductance would be several "
             "times larger and the ring-to-ball differences smaller.", "", *contacts, "",
             "![temperatures 1000](temperatures_1000rpm.png) "
             "![temperatures 1500](temperatures_1500rpm.png)", "",
             "![preload](preload.png) ![torque](torque.png) ![heat](heat.png)", ""]
    for n, paths in imgs.items():
        lines += [f"### Fields at {n:.0f} rpm", ""]
        lines += [f"![{p.stem}]({p.name})" for p in paths if "temperature" in p.name]
        lines.append("")
    (out / "report.md").write_text("\n".join(lines))
