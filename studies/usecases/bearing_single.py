"""`bearingfem bearing BEARING.toml LOADS.csv -o OUT.csv [--convention exact|iso16281]
[--control outer|inner|jones]`: one
bearing, rigid rings, inner ring with 5 DOF under the rows of LOADS.csv
(`analytic.bearing.single.solve_single`; docs/cli.md "Single bearing").

Columns in (any subset): radial_load_N (along x), radial_load_y_N, axial_load_N, moment_x_Nmm,
moment_y_Nmm, speed_rpm, T_oil_C (the oil's temperature, for its viscosity: required with an oil
[lubrication]).  A file with a speed_rpm column runs the quasi-dynamic ball model
(`analytic.bearing.ball_dynamics`, outer-race control unless --control says inner or jones;
identical to the quasi-static one at speed 0), otherwise the quasi-static one.  Columns out: the input columns, then OUTPUT_COLUMNS,
then `convention`.  Units in every name; displacements of the inner ring against the outer.
With a [lubrication] section in BEARING.toml, `torque_Nmm` is the bearing's friction torque by the
pair's torque model (analytic/torque.py) applied to this one bearing (`bearing_torque_Nmm`).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic.bearing.single import SingleBearingState, solve_single
from analytic.safety import static_load_rating_C0_N
from analytic.torque import (ContactInput, coulomb_load_torque_Nmm, palmgren_f1_angular_contact,
                             palmgren_load_torque_Nmm, palmgren_viscous_torque_Nmm,
                             solid_film_torque_Nmm)
from studies.model.config import load_bearing
from studies.model.table import TableError, read_table, write_table

LOAD_COLUMNS = ("radial_load_N", "radial_load_y_N", "axial_load_N", "moment_x_Nmm",
                "moment_y_Nmm", "speed_rpm", "T_oil_C")

#: output columns and their meaning (docs/cli.md "Single bearing")
OUTPUT_COLUMNS = {
    "radial_displacement_um": "magnitude of the inner ring's radial displacement",
    "radial_displacement_x_um": "its x component",
    "radial_displacement_y_um": "its y component",
    "axial_displacement_um": "axial displacement from the axially centred position",
    "tilt_mrad": "magnitude of the inner ring's tilt",
    "tilt_x_mrad": "tilt about x",
    "tilt_y_mrad": "tilt about y",
    "max_ball_load_N": "largest contact load of any ball (inner or outer contact)",
    "contact_angle_inner_deg": "inner contact angle of the most loaded ball",
    "contact_angle_outer_deg": "outer contact angle of the most loaded ball",
    "max_contact_pressure_MPa": "largest Hertz pressure over every ball and both contacts",
    "loaded_balls": "number of balls in contact with the inner ring",
    "centrifugal_force_N": "centrifugal force on a ball (most loaded ball's orbit)",
    "gyroscopic_moment_Nmm": "gyroscopic moment on the most loaded ball",
    "spin_to_roll": "spin-to-roll ratio at the inner contact of the most loaded ball",
    "outer_race_control": "1 where the outer raceway controls the most loaded ball, 0 the inner "
                          "(--control; empty without a speed_rpm column)",
    "torque_Nmm": "friction torque of the bearing (the pair's torque model, one bearing; empty "
                  "without [lubrication] in BEARING.toml)",
}


class BearingRunError(ValueError):
    """Bad input or a row without equilibrium: one line, exit 2."""


@dataclass(frozen=True)
class BearingRun:
    """What `bearing` computed: the single bearing's typed state and the output table (the load
    columns, then OUTPUT_COLUMNS, then `convention`)."""
    state: SingleBearingState
    columns: dict

    @property
    def n_rows(self) -> int:
        return len(self.columns["convention"])

    def to_frame(self):
        """OUT.csv's columns as a `pandas.DataFrame` (units in the names)."""
        import pandas as pd

        return pd.DataFrame(self.columns)


def run(bearing_path: Path, loads_path: Path, out: Path, convention: str = "exact",
        provenance: dict | None = None, control: str = "outer") -> int:
    """Solve every row of `loads_path` for the bearing of `bearing_path`, write `out` atomically
    (nothing is written when any row fails).  Returns the number of rows."""
    res = solve(load_bearing(bearing_path), read_table(loads_path, allowed=set(LOAD_COLUMNS)),
                str(loads_path), convention, control)
    write(res, out, provenance)
    return res.n_rows


def write(res: BearingRun, out: Path, provenance: dict | None = None) -> None:
    """OUT.csv and its provenance sidecar, atomically (a write error: one BearingRunError line)."""
    try:
        write_table(out, res.columns, provenance)
    except TableError as exc:
        raise BearingRunError(str(exc)) from None


def solve(cfg, cols: dict, where: str = "loads", convention: str = "exact",
          control: str = "outer") -> BearingRun:
    """Every row of the loads table `cols` (checked columns of LOAD_COLUMNS: from `read_table`,
    or the API's in-memory table; `where` names it in errors) for the bearing `cfg`
    (`load_bearing`)."""
    n = len(next(v for c, v in cols.items() if not c.startswith("_")))
    loads_path = where
    get = lambda c: np.asarray(cols.get(c, np.zeros(n)), float)  # noqa: E731
    quasi = "speed_rpm" in cols
    st = solve_single(cfg.geometry, axial_load_N=get("axial_load_N"),
                      radial_load_x_N=get("radial_load_N"), radial_load_y_N=get("radial_load_y_N"),
                      moment_x_Nmm=get("moment_x_Nmm"), moment_y_Nmm=get("moment_y_Nmm"),
                      speed_rpm=get("speed_rpm"),
                      ball_model="quasi_dynamic" if quasi else "static", convention=convention,
                      control=control)
    lub = cfg.lubrication
    if lub is not None and lub.kind == "oil" and "T_oil_C" not in cols:
        raise BearingRunError(f"{loads_path}: no T_oil_C column: an oil-lubricated bearing "
                              "([lubrication] kind = \"oil\") needs the oil temperature for its "
                              "viscosity")
    bad = np.flatnonzero(~st.converged)
    if bad.size:
        row = (f"line {cols['_line'][bad[0]]}" if "_line" in cols else f"row {bad[0] + 1}")
        raise BearingRunError(f"{loads_path}: {row}: no equilibrium found "
                              f"for these loads ({bad.size} row(s) in all); with radial "
                              "clearance a bearing needs a load that seats its balls")
    b = st.balls
    out_cols = {c: cols[c] for c in cols if not c.startswith("_")}
    out_cols.update({
        "radial_displacement_um": 1e3 * st.radial_mm,
        "radial_displacement_x_um": 1e3 * st.radial_x_mm,
        "radial_displacement_y_um": 1e3 * st.radial_y_mm,
        "axial_displacement_um": 1e3 * st.axial_mm,
        "tilt_mrad": 1e3 * st.tilt_rad, "tilt_x_mrad": 1e3 * st.tilt_x_rad,
        "tilt_y_mrad": 1e3 * st.tilt_y_rad,
        "max_ball_load_N": b.max_ball_load_N,
        "contact_angle_inner_deg": st.most_loaded("contact_angle_inner_deg"),
        "contact_angle_outer_deg": st.most_loaded("contact_angle_outer_deg"),
        "max_contact_pressure_MPa": b.max_contact_pressure_MPa.max(axis=0),
        "loaded_balls": (b.load_inner_N > 0.0).sum(axis=0),
        "centrifugal_force_N": st.most_loaded("centrifugal_force_N"),
        "gyroscopic_moment_Nmm": st.most_loaded("gyroscopic_moment_Nmm"),
        "spin_to_roll": st.most_loaded("spin_to_roll"),
        "outer_race_control": (st.most_loaded("outer_control").astype(float) if quasi
                               else np.full(n, np.nan)),
        "torque_Nmm": (np.full(n, np.nan) if lub is None else bearing_torque_Nmm(
            cfg, st, get("speed_rpm") if quasi else np.full(n, lub.speed_rpm), get("T_oil_C"))),
        "convention": np.full(n, convention),
    })
    return BearingRun(st, out_cols)


def bearing_torque_Nmm(cfg, st: SingleBearingState, speed_rpm, T_oil_C) -> np.ndarray:
    """Friction torque (N*mm) of one bearing in the state `st`, by the pair's torque model
    (`analytic.torque.pair_torque`, one bearing) with the file's [lubrication]:
    solid film: `solid_film_torque_Nmm` summed over every ball's own contacts (Z = 1 per ball:
      load, Hertz ellipse, inner and outer contact angle), mu = friction_coefficient, alpha_h =
      hysteresis_loss_factor; independent of the speed (a torque from a power per unit speed);
    oil: the load term (coulomb mu F_a dm/2, or palmgren f1 F_a dm with f1 = 0.001 (F_a/C0)^0.33,
      C0 of ISO 76) with F_a = |sum_k Q_k sin a_k| the axial force the balls carry (the applied
      axial load at equilibrium), plus Palmgren's viscous term 1e-7 f0 (nu n)^(2/3) dm^3 at the
      oil's viscosity at T_oil_C (its Walther law) and the inner ring's speed_rpm.
    speed_rpm and T_oil_C: (N,) per row."""
    lub, g, b = cfg.lubrication, cfg.geometry, st.balls
    if lub.kind == "solid_film":
        c_ring = (1.0 - g.ring.nu ** 2) / g.ring.E_MPa
        c_ball = (1.0 - g.ball.nu ** 2) / g.ball.E_MPa
        e_i, e_o = b.ellipse_inner, b.ellipse_outer
        inner = ContactInput(b.load_inner_N, e_i.a_mm, e_i.b_mm, e_i.E_ell, e_i.Rx_mm)
        outer = ContactInput(b.load_outer_N, e_o.a_mm, e_o.b_mm, e_o.E_ell, e_o.Rx_mm)
        dynamic = st.ball_model == "quasi_dynamic"
        t = solid_film_torque_Nmm(1, g.Dw_mm, g.dm_mm, g.f_i, g.f_o,
                                  np.radians(b.contact_angle_inner_deg), inner, outer,
                                  lub.friction_coefficient, lub.hysteresis_loss_factor, c_ring,
                                  c_ball, np.radians(b.contact_angle_outer_deg) if dynamic else None)
        return t.total_Nmm.sum(axis=0)
    Fa = np.abs(b.loads[0])
    if lub.load_term == "palmgren":
        C0 = static_load_rating_C0_N(g.Z, g.Dw_mm, g.dm_mm, g.alpha0_deg)
        load = palmgren_load_torque_Nmm(palmgren_f1_angular_contact(Fa, C0), Fa, g.dm_mm)
    else:
        load = coulomb_load_torque_Nmm(lub.friction_coefficient, Fa, 0.5 * g.dm_mm)
    nu = cfg.oil().nu_mm2_s(np.asarray(T_oil_C, float))
    return load + palmgren_viscous_torque_Nmm(lub.viscous_factor_f0, nu, speed_rpm, g.dm_mm)
