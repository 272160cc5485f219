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
speed with the EHL film in series (the oil's conductivity raised by the Hertz pressure, Larsson et
al. 2000), Blok's partition of each contact's heat (`analytic.heat.rolling_contact_conductance`),
refreshed from the contact state.
Three hours, as the seed's test.

Checked against the seed's qualitative findings (its section 3, fig. 9, at 1500 r/min, and its
conclusions 1 and 2): the balls are the hottest part, the inner ring warmer than the outer; the
temperature difference between the rings and the balls is below 4 K; the heat falls as the oil
thins and levels off (the total heat of the last half hour changes by less than 2 %). Each is
stated as found; `findings` returns them for the test. The seed publishes no equilibrium
temperature as a number (its figures 8, 9 and 12 are lost in our copy): this study states its own
(the report's table, docs/heatup.md), and why the balls run hotter than the rings: the heat
balance of each ball node at the end of the run, its resistances to the raceways
(`ball_balance`).
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from studies.model.config import Thermal, load_shipped
from studies.model.pipeline import Pipeline
from studies.model.table import write_table
from studies.model.transient_route import (TRANSIENT_COLUMNS, coupling_at, equilibrium,
                                           run_transient, thermal_model)
from studies.usecases.report_tools import line_plot, md_table

#: seed 003's statements (Li & Zhao, China Mechanical Engineering 34(7), 2023; our translation):
#: section 3 on its fig. 9 (1500 r/min, 1500 N axial, 50 N radial, 25 C ambient): "the balls'
#: temperature rise is higher than the rings'; as the system nears thermal equilibrium the
#: difference between inner and outer ring shrinks, and the difference between the rings and the
#: balls is below 4 C"; conclusion 1: "the balls are warmer than the rings, the inner ring warmer
#: than the outer"; section 3 on fig. 12b: the total heat quickly tends to a steady value. No
#: equilibrium temperature is given as a number (figs. 8, 9 and 12 are lost in our copy). The
#: ring-to-ball bound, K:
SEED_RING_BALL_DT_K = 4.0
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
    balances: tuple = ()            # `BallBalance` per bearing at the end (set by `run`)
    T_equilibrium_C: dict | None = None   # the fixed point of the steady state (set by `run`)
    upper: "UpperEnd | None" = None       # the same at the friction's upper end (set by `run`)


@dataclass(frozen=True)
class UpperEnd:
    """The steady state with the bearing's heat at the upper end of its friction torque's
    model-form interval (`analytic.friction.interval.lubrication_interval`): interval (its
    `ModelFormInterval`; NaN factors: none stated, nothing computed), T_C (part -> C), preload_N
    and heat_W (the pair's, both bearings) at that state."""
    interval: object
    T_C: dict
    preload_N: float
    heat_W: float


def conditions(speed_rpm: float, duration_s: float = DURATION_S, row_s: float = ROW_S) -> dict:
    """The study's conditions table at one speed: rows every row_s (s) over duration_s (s),
    ambient AMBIENT_C, preload PRELOAD_N."""
    t = np.arange(0.0, duration_s + 0.5 * row_s, row_s)
    n = t.size
    return {"time_s": t, "T_ambient_C": np.full(n, AMBIENT_C), "speed_rpm": np.full(n, speed_rpm),
            "preload_assembled_N": np.full(n, PRELOAD_N)}


def _parts_C(e) -> dict[str, float]:
    from studies.model.inputs import PARTS as GROUPS
    return {p: float(e.T_parts_C[GROUPS.index(p)]) for p in PARTS
            if np.isfinite(e.T_parts_C[GROUPS.index(p)])}


def equilibrium_C(pl: Pipeline, speed_rpm: float) -> dict[str, float]:
    """The equilibrium part temperatures (C) at speed_rpm: the fixed point of the coupled
    steady state (`transient_route.equilibrium`), where the heat-up ends if run for ever."""
    return _parts_C(equilibrium(pl, conditions(speed_rpm, 0.0)))


def upper_end(pl: Pipeline, speed_rpm: float) -> UpperEnd | None:
    """The equilibrium at speed_rpm with the bearing's heat x the upper factor of its friction
    torque's model-form interval (the heat of a torque x f is the heat x f: P = M omega), through
    the same fixed point (`transient_route.equilibrium(heat_factor=)`); None where the assembly's
    regime and law have no stated interval."""
    from analytic.friction.interval import lubrication_interval
    iv = lubrication_interval(pl.asm.lubrication)
    if not iv.stated:
        return None
    e = equilibrium(pl, conditions(speed_rpm, 0.0), heat_factor=iv.factor_hi)
    return UpperEnd(iv, _parts_C(e), float(e.coupling.result.pair.preload_N[0]),
                    float(e.coupling.heat.total_W[0]))


def heat_up(pl: Pipeline, speed_rpm: float, duration_s: float = DURATION_S,
            row_s: float = ROW_S, progress=None):
    """One heat-up: (rows' outputs, the `TransientRun`)."""
    cols = conditions(speed_rpm, duration_s, row_s)
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


@dataclass(frozen=True)
class BallBalance:
    """Heat balance of one bearing's ball node at the end of a run (the equilibrium), W and K.

    heat_W: the ball set's share of the heat of its contacts (`transient_route.coupling_at`);
    T_ball_C, T_race_inner_C, T_race_outer_C: the ball node and the mean temperatures of the two
    raceway faces it is linked to; inner, outer: the ball set-to-raceway conductances and their
    resistances per contact (`analytic.heat.ContactConductance`); G_holm_inner_W_K,
    G_holm_outer_W_K: what the classical lumped network takes instead (stationary Holm
    constriction, no film: `analytic.thermal_network.ball_raceway_resistance_K_W`)."""
    speed_rpm: float
    bearing: str
    heat_W: float
    T_ball_C: float
    T_race_inner_C: float
    T_race_outer_C: float
    inner: object
    outer: object
    G_holm_inner_W_K: float
    G_holm_outer_W_K: float

    @property
    def out_W(self) -> float:
        """Heat leaving the ball set into the two raceways, G_i (T_b - T_ri) + G_o (T_b - T_ro)."""
        return (self.inner.G_W_K * (self.T_ball_C - self.T_race_inner_C)
                + self.outer.G_W_K * (self.T_ball_C - self.T_race_outer_C))

    @property
    def film_share(self) -> float:
        """Share of the EHL film in one contact's resistance (inner and outer mean)."""
        f = [c.R_film_K_W / (c.R_ball_K_W + c.R_film_K_W + c.R_ring_K_W)
             for c in (self.inner, self.outer)]
        return float(np.mean(f))


def ball_balance(pl: Pipeline, cols: dict, run) -> list[BallBalance]:
    """The `BallBalance` of each bearing at the end of a heat-up (`heat_up`'s columns and run):
    the coupling at the last state (`transient_route.coupling_at`), the ball nodes' and the
    raceways' temperatures of that field."""
    from analytic.thermal_network import ball_raceway_resistance_K_W

    tm = thermal_model(pl)
    c = coupling_at(pl, cols, run.q[-1])
    T = tm.rc.field(run.q[-1])
    pair, g = c.result.pair, pl.geom
    k_ball = g.ball.conductivity_W_mK
    holm = []
    for side, con in (("inner", pair.inner), ("outer", pair.outer)):
        a, b = float(np.mean(con.a_mm[:, 0])), float(np.mean(con.b_mm[:, 0]))
        k_ring = pl.model.materials[f"{side}_ring_A"].conductivity_W_mK
        holm.append(1.0 / float(ball_raceway_resistance_K_W(a, b, k_ball, k_ring, g.Z)))
    out = []
    for j in tm.tc.bearings:
        out.append(BallBalance(float(cols["speed_rpm"][-1]), j, float(c.heat_inputs_W[f"ball_{j}"]),
                               tm.tc.mean_C(T, f"ball_{j}"),
                               tm.tc.mean_C(T, f"raceway_inner_ring_{j}"),
                               tm.tc.mean_C(T, f"raceway_outer_ring_{j}"),
                               c.contacts[0], c.contacts[1], holm[0], holm[1]))
    return out


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


def run(out: Path, progress=print, mesh_factor: float = 1.0, duration_s: float = DURATION_S,
        images: bool = True) -> dict[float, Findings]:
    """Write the study's tables, plots, field images and report into `out`; mesh_factor > 1
    coarsens the FE mesh (smoke tests). Returns the findings per speed."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    pl = Pipeline.shared(assembly(), mesh_factor=mesh_factor, progress=progress)
    res, found, imgs = {}, {}, {}
    balances = {}
    for n in SPEEDS_RPM:
        progress(f"heatup: {n:.0f} rpm, {duration_s / 3600:g} h ...")
        rows, r = heat_up(pl, n, duration_s, progress=progress)
        res[n] = rows
        balances[n] = ball_balance(pl, {k: rows[k] for k in TRANSIENT_COLUMNS if k in rows}, r)
        found[n] = replace(findings(rows, n), balances=tuple(balances[n]),
                           T_equilibrium_C=equilibrium_C(pl, n), upper=upper_end(pl, n))
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
    _report(out, found, res, tm.rc.m, imgs, balances)
    return found


def balance_lines(balances: dict) -> list[str]:
    """The report's lines on the ball nodes' heat balance at the end of each run (`BallBalance`)."""
    out = []
    for n, bb in balances.items():
        for b in bb:
            c_i, c_o = b.inner, b.outer
            out.append(
                f"- {n:.0f} rpm, bearing {b.bearing}: heat into the ball set {b.heat_W:.2f} W, "
                f"out to the raceways {b.out_W:.2f} W (balance residual {b.heat_W - b.out_W:+.1e} W); ball node {b.T_ball_C:.2f} C, inner "
                f"raceway {b.T_race_inner_C:.2f} C, outer raceway {b.T_race_outer_C:.2f} C; "
                f"ball set to inner raceway {c_i.G_W_K:.3f} W/K (per contact: ball side "
                f"{c_i.R_ball_K_W:.2f}, film {c_i.R_film_K_W:.2f}, ring side {c_i.R_ring_K_W:.2f} "
                f"K/W), to outer {c_o.G_W_K:.3f} W/K ({c_o.R_ball_K_W:.2f}, {c_o.R_film_K_W:.2f}, "
                f"{c_o.R_ring_K_W:.2f} K/W); film share of the resistance "
                f"{100 * b.film_share:.0f} %; the classical network's stationary Holm constriction "
                f"without film: {b.G_holm_inner_W_K:.3f} and {b.G_holm_outer_W_K:.3f} W/K")
    return out


def upper_end_lines(found: dict, res: dict) -> list[str]:
    """The report's section on the equilibrium at the friction's upper end (`UpperEnd`), its
    rise over the nominal equilibrium computed from the two fixed points."""
    ups = {n: f.upper for n, f in found.items() if f.upper is not None}
    if not ups:
        return ["## At the upper end of the friction torque", "",
                "No model-form interval is stated for this lubrication's regime and law "
                "(`analytic.friction.interval`): no upper-end heat-up is computed.", ""]
    iv = next(iter(ups.values())).interval
    rows = []
    for n, u in ups.items():
        f = found[n]
        rise = max(u.T_C[p] - f.T_equilibrium_C[p] for p in u.T_C)
        rows.append([f"{n:.0f}", *(f"{u.T_C[p]:.2f}" for p in PARTS if p in u.T_C),
                     f"{u.heat_W:.2f}", f"{u.preload_N:.0f}",
                     f"{res[n]['preload_N'][-1]:.0f}", f"{rise:+.2f}"])
    head = ["rpm", *(f"T_{p} (C)" for p in PARTS if p in next(iter(ups.values())).T_C),
            "heat (W)", "preload (N)", "preload at the end of the run (N)",
            "largest rise over the nominal fixed point (K)"]
    return ["## At the upper end of the friction torque", "",
            f"The same fixed point with the bearing's heat x {iv.factor_hi:.3g}, the upper factor of "
            f"the friction torque's {100 * iv.level:.0f} % model-form interval for a "
            f"{iv.regime.replace('_', ' ')} bearing with the {iv.law} law (x{iv.factor_lo:.3g} .. "
            f"x{iv.factor_hi:.3g}, from {iv.n_residuals} published points of "
            f"{', '.join(iv.sources)}: `analytic.friction.interval`). What the heat-up reaches if "
            "the friction is as high as the published points allow:", "",
            md_table(head, rows), ""]


def _report(out: Path, found: dict, res: dict, modes: int, imgs: dict, balances: dict) -> None:
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
            f"{SEED_RING_BALL_DT_K:g} K: {'yes' if f.ring_ball_dT_K < SEED_RING_BALL_DT_K else 'NO'}"
            f"); inner minus outer ring "
            f"{f.inner_outer_dT_K:+.2f} K (inner warmer: {'yes' if f.inner_outer_dT_K > 0 else 'NO'}"
            f"; largest over the run {f.inner_outer_dT_max_K:+.2f} K, shrinking since: "
            f"{'yes' if f.inner_outer_dT_K < f.inner_outer_dT_max_K else 'NO'}); heat at the end "
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
             "The seed publishes no equilibrium temperature as a number (its figures are lost in "
             "our copy); these are this model's.", "",
             md_table(head, rows), "",
             "The same equilibrium found without time stepping, as the fixed point of the coupled "
             "steady state (`transient_route.equilibrium`), C:", "",
             md_table(["rpm", *(f"T_{p} (C)" for p in PARTS if p in found[SPEEDS_RPM[0]].T_end_C),
                       "largest |end of run - fixed point| (K)"],
                      [[f"{n:.0f}", *(f"{f.T_equilibrium_C[p]:.3f}" for p in PARTS
                                      if p in f.T_end_C),
                        f"{max(abs(f.T_end_C[p] - f.T_equilibrium_C[p]) for p in f.T_end_C):.1e}"]
                       for n, f in found.items()]), "",
             *upper_end_lines(found, res),
             "## The seed's findings", "", *checks, "",
             "## Why the balls run hotter: the ball nodes' heat balance at the end of the run", "",
             "Each ball set takes its share of its contacts' heat (Blok's partition, one half "
             "for steel on steel) and passes it to the raceways through the contacts only: per "
             "contact the ball-side and ring-side moving-source constrictions and the EHL film in "
             "series, the film's oil conductivity raised by the Hertz pressure (Larsson et al. "
             "2000, `analytic.heat.oil_conductivity_ratio`). Left out, each would cool the balls "
             "further (docs/heatup.md): the oil meniscus around each contact and the ball's "
             "convection to the cavity air.", "", *balance_lines(balances), "",
             "![temperatures 1000](temperatures_1000rpm.png) "
             "![temperatures 1500](temperatures_1500rpm.png)", "",
             "![preload](preload.png) ![torque](torque.png) ![heat](heat.png)", ""]
    for n, paths in imgs.items():
        lines += [f"### Fields at {n:.0f} rpm", ""]
        lines += [f"![{p.stem}]({p.name})" for p in paths if "temperature" in p.name]
        lines.append("")
    (out / "report.md").write_text("\n".join(lines))
