"""Study `tvac`: seed 000's stack (NSK 71807C pair, back-to-back, 9Cr18 rings and balls in a TC4
shaft and housing, MoS2 film, 100 N position preload, 60 rpm) through a thermal-vacuum cycle,
through `simulate`'s transient route (studies/model/transient_route.py; the same route and
machinery as the `heatup` study): no convection, every exterior face radiating to the chamber's
shroud (the sink) as it follows the cycle, the part temperatures, preload and torque computed
against time.

Set-up (assumptions, stated): vacuum (`[thermal] gas = "vacuum"`: no gas in the fits' gaps, an
open fit conducts nothing), no films; emissivity 0.3 on every exterior face but the raceways
(bare machined Ti-6Al-4V and ground 9Cr18, 0.2-0.4: Gilmore, Spacecraft Thermal Control
Handbook Vol. I, 2nd ed. 2002, App. A; the faces inside the bearing cavity radiate to the sink
too, a simplification: they see mostly each other); the ball contacts at the stationary limit of
the rolling constriction at 60 rpm, no EHL film (a solid film). The cycle (shroud temperature,
linear between the points): 20 C, up to +60 C in 2 h, 4 h dwell, down to -40 C in 3 h, 4 h dwell,
back to 20 C in 2 h (15 h). The bearing's own friction heat (MoS2, 60 rpm) is fed back as in the
heat-up, a few mW here.

Outputs: `tvac.csv` (time, shroud temperature, part temperatures, preload, torque, heat, the
reduction's error estimate), `tvac.png` (temperature, preload and torque against time, three
panels), temperature and displacement field images at INSTANTS_H, `report.md`.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from studies.model.config import Thermal, load_shipped
from studies.model.pipeline import Pipeline
from studies.model.table import write_table
from studies.model.transient_route import run_transient, thermal_model
from studies.validation.heatup import field_images
from studies.usecases.report_tools import md_table

#: shroud (sink) temperature of the cycle: (time h, C), linear in between
CYCLE_H_C = ((0.0, 20.0), (2.0, 60.0), (6.0, 60.0), (9.0, -40.0), (13.0, -40.0), (15.0, 20.0))
EMISSIVITY = 0.3
ROW_S = 300.0
#: step of the transient (s): radiation-only time constants are hours; the coupling every 3 steps
DT_S = 10.0
COUPLE_EVERY = 3
#: instants of the field images (h): end of the hot ramp and dwell, mid cold ramp, end of the cold dwell
INSTANTS_H = (2.0, 6.0, 7.5, 13.0)
PARTS = ("shaft", "inner_ring", "ball", "outer_ring", "housing", "spacer")


def assembly():
    """Seed 000's assembly in transient mode, in vacuum, radiating to the sink."""
    return replace(load_shipped("seed000"),
                   thermal=Thermal(mode="transient", films=(), emissivity=EMISSIVITY,
                                   gas="vacuum"))


def conditions(time_scale: float = 1.0, row_s: float = ROW_S) -> dict:
    """The cycle's rows: time_s, T_sink_C (time_scale < 1 compresses the cycle: smoke tests)."""
    th = np.array([p[0] for p in CYCLE_H_C]) * 3600.0 * time_scale
    t = np.arange(0.0, th[-1] + 0.5 * row_s, row_s)
    return {"time_s": t, "T_sink_C": np.interp(t, th, [p[1] for p in CYCLE_H_C])}


@dataclass(frozen=True)
class CycleSummary:
    """What the cycle does to the stack. T_range_C: part -> (min, max) over the cycle (C);
    preload_range_N, torque_range_Nmm: (min, max); lag_h: time (h) from the shroud's
    hot-dwell start to the housing reaching 95 % of the way (NaN if it does not);
    shaft_minus_housing_K: (min, max) of T_shaft - T_housing (the transient gradient)."""
    T_range_C: dict
    preload_range_N: tuple
    torque_range_Nmm: tuple
    lag_h: float
    shaft_minus_housing_K: tuple


def summary(rows: dict, time_scale: float = 1.0) -> CycleSummary:
    t = rows["time_s"]
    T = {p: (float(rows[f"T_{p}_C"].min()), float(rows[f"T_{p}_C"].max()))
         for p in PARTS if f"T_{p}_C" in rows}
    t0 = CYCLE_H_C[1][0] * 3600.0 * time_scale
    goal = CYCLE_H_C[0][1] + 0.95 * (CYCLE_H_C[1][1] - CYCLE_H_C[0][1])
    hit = np.flatnonzero((t >= t0) & (rows["T_housing_C"] >= goal))
    lag = float((t[hit[0]] - t0) / 3600.0) if hit.size else float("nan")
    d = rows["T_shaft_C"] - rows["T_housing_C"]
    rng = lambda v: (float(np.min(v)), float(np.max(v)))     # noqa: E731
    return CycleSummary(T, rng(rows["preload_N"]), rng(rows["torque_Nmm"]), lag, rng(d))


def cycle_plot(path: Path, rows: dict) -> Path:
    """Temperature (shroud and parts), preload and torque against time: three panels."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = rows["time_s"] / 3600.0
    fig, ax = plt.subplots(3, 1, figsize=(7.0, 8.0), sharex=True)
    ax[0].plot(t, rows["T_sink_C"], "k--", lw=1.0, label="shroud (sink)")
    for p in PARTS:
        if f"T_{p}_C" in rows:
            ax[0].plot(t, rows[f"T_{p}_C"], lw=1.2, label=p)
    ax[0].set_ylabel("temperature (C)")
    ax[0].legend(fontsize=7, ncol=2)
    ax[1].plot(t, rows["preload_N"], lw=1.2)
    ax[1].set_ylabel("preload (N)")
    ax[2].plot(t, rows["torque_Nmm"], lw=1.2)
    ax[2].set_ylabel("friction torque (N mm)")
    ax[2].set_xlabel("time (h)")
    for a in ax:
        a.grid(alpha=0.3)
    ax[0].set_title("Seed 000 stack in a thermal-vacuum cycle (transient FE, reduced)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def run(out: Path, progress=print, mesh_factor: float = 1.0, time_scale: float = 1.0,
        images: bool = True, dt_s: float = DT_S) -> CycleSummary:
    """Write the study's table, plot, field images and report into `out`; mesh_factor > 1
    coarsens the FE mesh, time_scale < 1 compresses the cycle and dt_s (s) sets the step
    (smoke tests)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    a = assembly()
    pl = Pipeline.shared(a, mesh_factor=mesh_factor, progress=progress)
    cols = conditions(time_scale)
    progress(f"tvac: {cols['time_s'][-1] / 3600:g} h cycle ...")
    r = run_transient(pl, cols, progress, couple_every=COUPLE_EVERY, dt_s=dt_s)
    rows = {**cols, **r.columns()}
    keep = ["time_s", "T_sink_C", *(f"T_{p}_C" for p in PARTS), "T_max_C", "T_min_C",
            "preload_N", "torque_Nmm", "heat_bearing_W", "fit_pressure_inner_MPa",
            "fit_pressure_outer_MPa", "reduction_error_est"]
    write_table(out / "tvac.csv", {k: rows[k] for k in keep if k in rows})
    cycle_plot(out / "tvac.png", rows)
    s = summary(rows, time_scale)
    imgs = []
    if images:
        speed = a.lubrication.speed_rpm
        imgs = field_images(out, pl, r, [h * 3600.0 * time_scale for h in INSTANTS_H], speed,
                            a.preload.assembled_N, "tvac",
                            label=lambda ts: f"t = {ts / 3600:.1f} h")
    _report(out, s, rows, thermal_model(pl).rc.m, imgs)
    return s


def _report(out: Path, s: CycleSummary, rows: dict, modes: int, imgs: list) -> None:
    head = ["part", "min (C)", "max (C)"]
    trows = [[p, f"{lo:.2f}", f"{hi:.2f}"] for p, (lo, hi) in s.T_range_C.items()]
    err = float(np.max(rows["reduction_error_est"]))
    cyc = ", ".join(f"{h:g} h: {T:g} C" for h, T in CYCLE_H_C)
    lines = ["# Seed 000's stack in a thermal-vacuum cycle (transient conduction FE)", "",
             __doc__.split("\n\n")[1].replace("\n", " "), "",
             f"Cycle (shroud): {cyc}. Reduced model: {modes} thermal modes; largest estimated "
             f"relative preload error of the reduction {err:.1e} (`reduction_error_est`).", "",
             "## Temperatures over the cycle", "", md_table(head, trows), "",
             f"- preload {s.preload_range_N[0]:.1f} .. {s.preload_range_N[1]:.1f} N "
             f"(assembled {float(rows['preload_N'][0]):.1f} N at the start)",
             f"- friction torque {s.torque_range_Nmm[0]:.2f} .. {s.torque_range_Nmm[1]:.2f} N mm",
             f"- shaft minus housing {s.shaft_minus_housing_K[0]:+.2f} .. "
             f"{s.shaft_minus_housing_K[1]:+.2f} K (the transient gradient: the shaft is "
             "linked to the housing only through the ball contacts)",
             f"- the housing reaches 95 % of the hot step {s.lag_h:.2f} h after the shroud "
             "(radiation only: time constants of hours)", "",
             "![temperature, preload and torque](tvac.png)", "", "## Fields", ""]
    lines += [f"![{p.stem}]({p.name})" for p in imgs if "temperature" in p.name]
    lines.append("")
    (out / "report.md").write_text("\n".join(lines))
