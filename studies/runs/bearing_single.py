"""`bearingfem bearing BEARING.toml LOADS.csv -o OUT.csv [--convention exact|iso16281]
[--control outer|inner|jones]`: one
bearing, rigid rings, inner ring with 5 DOF under the rows of LOADS.csv
(`analytic.bearing.single.solve_single`; shared/spec/cli.md section "bearing").

Columns in (any subset): radial_load_N (along x), radial_load_y_N, axial_load_N, moment_x_Nmm,
moment_y_Nmm, speed_rpm.  A file with a speed_rpm column runs the quasi-dynamic ball model
(`analytic.bearing.ball_dynamics`, outer-race control unless --control says inner or jones;
identical to the quasi-static one at speed 0), otherwise the quasi-static one.  Columns out: the input columns, then OUTPUT_COLUMNS,
then `convention`.  Units in every name; displacements of the inner ring against the outer.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from analytic.bearing.single import solve_single
from studies.model.config import load_bearing
from studies.model.table import TableError, read_table, write_table

LOAD_COLUMNS = ("radial_load_N", "radial_load_y_N", "axial_load_N", "moment_x_Nmm",
                "moment_y_Nmm", "speed_rpm")

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
}


class BearingRunError(ValueError):
    """Bad input or a row without equilibrium: one line, exit 2."""


def run(bearing_path: Path, loads_path: Path, out: Path, convention: str = "exact",
        provenance: dict | None = None, control: str = "outer") -> int:
    """Solve every row of `loads_path` for the bearing of `bearing_path`, write `out` atomically
    (nothing is written when any row fails).  Returns the number of rows."""
    cfg = load_bearing(bearing_path)
    cols = read_table(loads_path, allowed=set(LOAD_COLUMNS))
    n = len(cols["_line"])
    get = lambda c: np.asarray(cols.get(c, np.zeros(n)), float)  # noqa: E731
    quasi = "speed_rpm" in cols
    st = solve_single(cfg.geometry, axial_load_N=get("axial_load_N"),
                      radial_load_x_N=get("radial_load_N"), radial_load_y_N=get("radial_load_y_N"),
                      moment_x_Nmm=get("moment_x_Nmm"), moment_y_Nmm=get("moment_y_Nmm"),
                      speed_rpm=get("speed_rpm"),
                      ball_model="quasi_dynamic" if quasi else "static", convention=convention,
                      control=control)
    bad = np.flatnonzero(~st.converged)
    if bad.size:
        raise BearingRunError(f"{loads_path}: line {cols['_line'][bad[0]]}: no equilibrium found "
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
        "convention": np.full(n, convention),
    })
    try:
        write_table(out, out_cols, provenance)
    except TableError as exc:
        raise BearingRunError(str(exc)) from None
    return n
