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
friction route `simulate` takes (analytic/friction/) on this bearing's balls (`bearing_friction_of`).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic.bearing.single import SingleBearingState, solve_single
from analytic.safety import static_load_rating_C0_N
from analytic.thermal_speed import (ThermalReference, dissipated_heat_W,
                                    reference_heat_transfer_W_per_mm2_K, thermal_reference_speed,
                                    thermally_permissible_speed)
from analytic.friction.pair import BearingFriction, bearing_friction, single_bearing_contacts
from analytic.friction.ranges import notes
from analytic.friction.palmgren import palmgren_f1_angular_contact, palmgren_load_torque_Nmm
from studies.model.stages.torque import friction_options
from studies.model.table import TableError, write_table

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
    "torque_lo_Nmm": "lower bound of the friction law's model-form interval on torque_Nmm "
                     "(90 % nominal, study friction_validation; empty where none is stated)",
    "torque_hi_Nmm": "its upper bound",
    "heat_lo_W": "the same interval on the bearing's friction heat torque_Nmm x omega",
    "heat_hi_W": "its upper bound",
    "thermal_reference_speed_rpm": "thermal reference speed, ISO 15312:2018 (the same on every "
                                   "row; analytic/thermal_speed.py)",
    "thermal_permissible_speed_rpm": "thermally permissible speed, DIN 732:2010 with the friction "
                                     "of ISO/TR 14179-2 at the row's load, the oil's viscosity "
                                     "at the permissible temperature (empty without an oil "
                                     "[lubrication])",
    "margin_speed_rpm": "thermal_permissible_speed_rpm - the row's speed",
    "thermal_permissible_speed_hi_rpm": "the DIN 732 speed at the upper end of the friction "
                                        "law's model-form interval (torque_hi_Nmm's factor)",
    "margin_speed_hi_rpm": "thermal_permissible_speed_hi_rpm - the row's speed",
}


class BearingRunError(ValueError):
    """Bad input or a row without equilibrium: one line, exit 2."""


@dataclass(frozen=True)
class BearingRun:
    """What `bearing` computed: the single bearing's typed state and the output table (the load
    columns, then OUTPUT_COLUMNS, then `convention`)."""
    state: SingleBearingState
    columns: dict
    warnings: tuple[str, ...] = ()

    @property
    def n_rows(self) -> int:
        return len(self.columns["convention"])

    def to_frame(self):
        """OUT.csv's columns as a `pandas.DataFrame` (units in the names)."""
        import pandas as pd

        return pd.DataFrame(self.columns)


def write(res: BearingRun, out: Path, provenance: dict | None = None) -> None:
    """OUT.csv and its provenance sidecar, atomically (a write error: one BearingRunError line)."""
    try:
        write_table(out, res.columns, provenance)
    except TableError as exc:
        raise BearingRunError(str(exc)) from None


def solve(cfg, cols: dict, where: str = "loads", convention: str = "exact",
          control: str = "outer", bearing_name: str = "bearing") -> BearingRun:
    """Every row of the loads table `cols` (checked columns of LOAD_COLUMNS: from `read_table`,
    or the API's in-memory table; `where` names it in errors) for the bearing `cfg`
    (`load_bearing`; `bearing_name` names it in warning lines)."""
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
    speed = get("speed_rpm") if quasi else np.full(n, 0.0 if lub is None else lub.speed_rpm)
    fric = None if lub is None else bearing_friction_of(cfg, st, speed, get("T_oil_C"))
    torque = np.full(n, np.nan) if fric is None else fric.total_Nmm
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
        "torque_Nmm": torque,
    })
    out_cols.update(_interval_columns(lub, torque, speed))
    ts = thermal_speeds(cfg.spec, cfg.geometry, lub, cfg.oil(), np.abs(b.loads[0]), speed)
    out_cols.update({"thermal_reference_speed_rpm": np.full(n, ts.reference.speed_rpm),
                     "thermal_permissible_speed_rpm": ts.permissible_speed_rpm,
                     "margin_speed_rpm": ts.margin_speed_rpm,
                     "thermal_permissible_speed_hi_rpm": _or_nan(ts.permissible_speed_hi_rpm, n),
                     "margin_speed_hi_rpm": _or_nan(ts.margin_speed_hi_rpm, n),
                     "convention": np.full(n, convention)})
    warnings = [f"{bearing_name}: {ts.warning}"] if ts.warning else []
    if fric is not None:
        warnings += [f"{bearing_name}: {r.message(n)}" for r in notes(fric.ranges)]
    return BearingRun(st, out_cols, tuple(warnings))


def _or_nan(v, n: int) -> np.ndarray:
    return np.full(n, np.nan) if v is None else np.asarray(v, float)


def lubrication_interval(lub):
    """The friction law's model-form interval of a `[lubrication]`
    (`analytic.friction.interval.lubrication_interval`)."""
    from analytic.friction.interval import lubrication_interval as interval
    return interval(lub)


def _interval_columns(lub, torque_Nmm, speed_rpm) -> dict:
    """torque_lo/hi_Nmm and heat_lo/hi_W: the friction law's model-form interval
    (`analytic.friction.interval.lubrication_interval`, the factors `simulate` applies) on the
    torque and on its heat M omega (`analytic.torque.power_W`); NaN without a [lubrication] or
    where no interval is stated."""
    from analytic.torque import power_W
    M = np.asarray(torque_Nmm, float)
    lo = hi = np.full(M.shape, np.nan)
    if lub is not None:
        lo, hi = lubrication_interval(lub).apply(M)
    n = np.broadcast_to(np.asarray(speed_rpm, float), M.shape)
    return {"torque_lo_Nmm": lo, "torque_hi_Nmm": hi,
            "heat_lo_W": power_W(lo, n), "heat_hi_W": power_W(hi, n)}


def bearing_friction_of(cfg, st: SingleBearingState, speed_rpm, T_oil_C) -> BearingFriction:
    """Friction (`BearingFriction`: torque N*mm by term, the rows outside the law's range) of
    one bearing in the state `st`, by the friction route of
    `simulate` (`analytic.friction.pair.bearing_friction` on every ball's own contacts,
    `single_bearing_contacts`; the law's options from the file's [lubrication] by
    `studies.model.stages.torque.friction_options`, as `simulate` builds them):
    solid film: mu = friction_coefficient (or the pressure-dependent shear strength),
      alpha_h = hysteresis_loss_factor; independent of the speed;
    oil: the viscous_model's terms (palmgren, skf2004, ehl_rolling, starved) at the oil's
      viscosity at T_oil_C (its Walther law) and the inner ring's speed_rpm, with the load term
      (coulomb mu F_a dm/2, or palmgren f1 F_a dm with f1 = 0.001 (F_a/C0)^0.33, C0 of ISO 76;
      F_a = |sum_k Q_k sin a_k| the axial force the balls carry).
    speed_rpm and T_oil_C: (N,) per row."""
    lub, g = cfg.lubrication, cfg.geometry
    contacts = single_bearing_contacts(st)
    if lub.kind == "solid_film":
        return bearing_friction(g, contacts, model="solid_film", mu=lub.friction_coefficient,
                                hysteresis_loss=lub.hysteresis_loss_factor,
                                friction=friction_options(lub, None, cfg.spec, None))
    oil = cfg.oil()
    nu = oil.nu_mm2_s(np.asarray(T_oil_C, float))
    f1 = None
    if lub.load_term == "palmgren":
        C0 = static_load_rating_C0_N(g.Z, g.Dw_mm, g.dm_mm, g.alpha0_deg)
        f1 = palmgren_f1_angular_contact(contacts.axial_force_N, C0)
    return bearing_friction(g, contacts, model="oil", mu=lub.friction_coefficient,
                            speed_rpm=np.asarray(speed_rpm, float), f0=lub.viscous_factor_f0,
                            nu_mm2_s=nu, f1=f1, load_term=lub.load_term,
                            friction=friction_options(lub, oil, cfg.spec, nu))


#: the default f0r when [lubrication] reference_f0r is 0 or absent: Palmgren's oil-bath f0 of a
#: single-row ball bearing (Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 2 ch.
#: "friction", table of f0; ball bearings range from about 1.3 to 3.3 with the type): the maker's
#: f0r (ISO 15312 Annex A) should replace it, hence the warning
DEFAULT_F0R = 2.0


@dataclass(frozen=True)
class ThermalSpeeds:
    """The thermal speed limits of one bearing (analytic/thermal_speed.py), arrays over rows:
    reference (ISO 15312, `ThermalReference`), permissible_speed_rpm (DIN 732; NaN without an
    oil), margin_speed_rpm (permissible - speed), defaults: the keys whose default was used;
    permissible_speed_hi_rpm, margin_speed_hi_rpm: the same at the upper end of the friction
    law's model-form interval (`analytic.friction.interval`; NaN where none is stated)."""
    reference: ThermalReference
    permissible_speed_rpm: np.ndarray
    margin_speed_rpm: np.ndarray
    defaults: tuple[str, ...]
    permissible_speed_hi_rpm: np.ndarray | None = None
    margin_speed_hi_rpm: np.ndarray | None = None

    @property
    def warning(self) -> str | None:
        """One line naming the defaults used, None when every key was given."""
        if not self.defaults:
            return None
        return ("thermal speeds use default(s) " + ", ".join(self.defaults)
                + " (docs/cli.md \"Thermal speed limits\"; set them in [lubrication])")


def thermal_speeds(spec, g, lub, oil, axial_force_N, speed_rpm) -> ThermalSpeeds:
    """ISO 15312 thermal reference speed and DIN 732 thermally permissible speed of the bearing
    `spec` (boundary dimensions; `g` its `BearingGeometry`: C0 of ISO 76) with the [lubrication]
    `lub` (None: every default) and its oil `oil` (None: no permissible speed). Per row: the
    axial force the bearing carries (N) and the speed (rpm).
    DIN 732's heat balance puts the bearing at its permissible temperature: the oil's viscosity
    is taken there ([lubrication] permissible_temperature_C, 70 C by default, the ISO 15312
    reference), not at the row's temperature, so the permissible speed of a bearing does not
    depend on the row's temperature; the load term is the standard's M1 = f1 P1 dm (ISO/TR
    14179-2: f1 = 0.001 (P1/C0)^0.33, P1 = F_a for the axially loaded pair), whatever load
    term the file's friction torque uses.
    f0r, f1r, k_q, the permissible and ambient temperatures from `lub` (0 or None: defaults,
    see `studies.model.assembly.Lubrication`); the heat-emitting surface pi B (D + d) from the
    boundary dimensions (ISO 15312 defines it so)."""
    C0 = float(static_load_rating_C0_N(g.Z, g.Dw_mm, g.dm_mm, g.alpha0_deg))
    defaults = []
    f0r = getattr(lub, "reference_f0r", 0.0) or 0.0
    if f0r <= 0:
        f0r = DEFAULT_F0R
        defaults.append(f"reference_f0r = {DEFAULT_F0R:g}")
    f1r = getattr(lub, "reference_f1r", 0.0) or 0.0
    if f1r <= 0:                     # Palmgren's f1 at the reference load (a formula, no warning)
        f1r = float(palmgren_f1_angular_contact(0.05 * C0, C0))
    ref = thermal_reference_speed(spec.bore_mm, spec.outside_diameter_mm, spec.width_mm, C0,
                                  f0r, f1r)
    speed = np.asarray(speed_rpm, float)
    if lub is None or oil is None:
        nan = np.full(speed.shape, np.nan)
        return ThermalSpeeds(ref, nan, nan, tuple(defaults))
    k_q = lub.heat_transfer_W_per_mm2_K
    if k_q <= 0:
        k_q = float(reference_heat_transfer_W_per_mm2_K(ref.surface_mm2))
        defaults.append(f"heat_transfer_W_per_mm2_K = {k_q:.3g}")
    Q = dissipated_heat_W(k_q, ref.surface_mm2, lub.permissible_temperature_C,
                          lub.ambient_temperature_C)
    nu = float(oil.nu_mm2_s(lub.permissible_temperature_C))
    Fa = np.asarray(axial_force_N, float)
    M1 = palmgren_load_torque_Nmm(palmgren_f1_angular_contact(Fa, C0), Fa, g.dm_mm)
    perm = thermally_permissible_speed(ref.speed_rpm, lub.viscous_factor_f0, nu, g.dm_mm, M1,
                                       Q * np.ones_like(speed)).speed_rpm
    # the upper end of the friction law's interval: friction x factor_hi = Q is the balance
    # friction = Q / factor_hi (both of DIN 732's terms scale alike)
    k_hi = lubrication_interval(lub).factor_hi
    perm_hi = (np.full(speed.shape, np.nan) if not np.isfinite(k_hi) else
               thermally_permissible_speed(ref.speed_rpm, lub.viscous_factor_f0, nu, g.dm_mm, M1,
                                           Q / k_hi * np.ones_like(speed)).speed_rpm)
    return ThermalSpeeds(ref, perm, perm - np.abs(speed), tuple(defaults), perm_hi,
                         perm_hi - np.abs(speed))
