"""The one writer of named columns: a `SimulationResult` as the output columns of
`bearingfem simulate` (docs/cli.md), in the order the command writes them.

Used at the file and API edges only: the `simulate` stream, the Python API, the studies' tables
and whatever compares a column by name (the diagnosis). Units are converted here where a column's
unit differs from the field's (groove shifts and raceway displacements mm -> um, rotor radial
displacement mm -> um, tilt rad -> mrad); nothing else is computed.
"""
from __future__ import annotations

import numpy as np

from studies.model.checks import Checks
from studies.model.result import SimulationResult

AB = "AB"


def to_columns(result: SimulationResult, flags: bool = True, friction_split: bool = False,
               only: tuple[str, ...] | None = None) -> dict[str, np.ndarray]:
    """{column name: (n,) array} of a result: headline outputs, torque components, fit
    pressures, Lamé neighbours, groove shifts, per-bearing forces and angles, ball and load
    columns, land margins, checks' values; with `friction_split`, the torque by kind and the
    heat by location (`friction_split_columns`, after every other model column: the columns
    before them keep their order); with `flags`, then each check's `flag_<name>`
    (1 = violated) and `margin_<name>` columns (docs/cli.md, "simulate: limits").
    `simulate` writes the split (its stream, its transient mode and the Python API ask for it);
    the studies' and the report's tables are written without it, so the shipped seed CSVs stay
    byte-identical to the Palmgren files. `only`: just these columns, in this order
    (KeyError for a name not written); the Lamé neighbours (`result.lame`) are computed only
    when one of their columns (`lame_column_names`) is among them (a diagnosis compares none)."""
    fe, pair, t, s = result.fe, result.pair, result.torque, result.summary
    out = {"torque_Nmm": t.torque_Nmm, "preload_N": pair.preload_N,
           "contact_angle_deg": s.contact_angle_deg,
           "interference_inner_um": fe.interference_um[:, 0],
           "interference_outer_um": fe.interference_um[:, 1],
           **_layer_interference_columns(result),
           "fit_pressure_inner_MPa": result.fits.inner_MPa,
           "fit_pressure_outer_MPa": result.fits.outer_MPa,
           "max_contact_pressure_MPa": pair.max_contact_pressure_MPa}
    out.update(_torque_columns(t))
    for k, name in enumerate(result.fits.names):
        if name.startswith("fit_"):              # (a clamped face's pressure: `_clamp_columns`)
            out[f"{name.replace('fit_', 'fit_pressure_')}_MPa"] = result.fits.per_fit_MPa[:, k]
    if only is None or not set(only).isdisjoint(lame_column_names(result.layer_names)):
        out.update(_lame_columns(result))
    for j, J in enumerate(AB):
        out[f"groove_shift_dr_{J}_um"] = 1e3 * fe.dr_mm[j]
        out[f"groove_shift_dz_{J}_um"] = 1e3 * fe.dz_mm[j]
    for j, J in enumerate(AB):
        out[f"axial_force_{J}_N"] = pair.axial_force_N[j]
    for j, J in enumerate(AB):
        out[f"contact_angle_{J}_deg"] = pair.contact_angle_deg[j]
    for j, J in enumerate(AB):
        out[f"ball_load_{J}_N"] = pair.ball_load_N[j]
    out.update(_ball_columns(pair))
    out["axial_stiffness_N_per_um"] = pair.pair_axial_stiffness_N_per_um
    out.update(_load_columns(pair))
    out["land_margin_inner_deg"] = s.land_margin_inner_deg
    out["land_margin_outer_deg"] = s.land_margin_outer_deg
    out["preload_lost"] = pair.preload_lost.astype(float)
    out["static_safety"] = s.static_safety
    out["friction_coefficient"] = result.friction_coefficient
    out.update(_clamp_columns(result))
    if friction_split:
        out.update(friction_split_columns(result.torque))
        out.update(interval_columns(result.torque))
    if flags:
        out.update(check_columns(result.checks))
    return out if only is None else {c: out[c] for c in only}


def check_columns(checks: Checks) -> dict[str, np.ndarray]:
    """Each check's `flag_<name>` (1 = violated) and `margin_<name>` columns (a strict check: its
    `margin_column` in its own unit, or none), in the checks' order: the last columns of
    `to_columns`."""
    out = {}
    for o in checks.outcomes:
        out[f"flag_{o.check.name}"] = o.violated.astype(float)
        if o.margin is not None:
            out[o.check.margin_column or f"margin_{o.check.name}"] = o.margin
    return out


def _layer_interference_columns(result: SimulationResult) -> dict[str, np.ndarray]:
    """`interference_<layer>_um` of each sleeve / cartridge (free diametral overlap of its fit at
    the row's temperatures; NaN for a conduction-field state), none without layers."""
    fe, names = result.fe, result.layer_names
    li = fe.layer_interference_um
    n = fe.interference_um.shape[0]
    return {f"interference_{name}_um": np.full(n, np.nan) if li is None else li[:, k]
            for k, name in enumerate(names)}


def _clamp_columns(result: SimulationResult) -> dict[str, np.ndarray]:
    """With a clamp of clamp = "force" only (other assemblies keep their columns): the clamp
    force at the row's state (N; of the clamp with the least margin when nut and cover both
    have one) and `margin_clamp_N`, the force left before a face opens (`stages.fe.ClampState`)."""
    c = result.clamp
    if c is None:
        return {}
    return {"clamp_force_N": c.force_N.min(axis=1), "margin_clamp_N": c.margin_N}


def _torque_columns(t) -> dict[str, np.ndarray]:
    """The torque components after `torque_Nmm`: solid film, the dissipations and the contact
    sums; oil, the load and viscous terms (ehl_rolling: and the spin sliding); then per bearing, the heat and (oil) the viscosity."""
    if t.model == "solid_film":
        out = {"torque_hysteresis_Nmm": t.hysteresis_Nmm,
               "torque_differential_Nmm": t.differential_Nmm, "torque_spin_Nmm": t.spin_Nmm,
               "torque_inner_contacts_Nmm": t.inner_contacts_Nmm,
               "torque_outer_contacts_Nmm": t.outer_contacts_Nmm}
    else:
        out = {"torque_load_Nmm": t.load_Nmm, "torque_viscous_Nmm": t.viscous_Nmm}
        if t.spin_Nmm is not None:          # ehl_rolling: the contacts' spin sliding
            out["torque_spin_Nmm"] = t.spin_Nmm
    out["torque_A_Nmm"], out["torque_B_Nmm"] = t.torque_A_Nmm, t.torque_B_Nmm
    if t.heat_W is not None:
        out["heat_W"] = t.heat_W
    if t.model == "oil":
        out["viscosity_mm2_s"] = t.viscosity_mm2_s
    return out


#: the friction split's column names (`friction_split_columns`): the torque by kind, then the
#: heat by where it is made
FRICTION_SPLIT_TORQUE = ("torque_rolling_Nmm", "torque_sliding_Nmm", "torque_drag_Nmm")
FRICTION_SPLIT_HEAT = ("heat_inner_W", "heat_outer_W", "heat_ball_W")


def friction_split_columns(t) -> dict[str, np.ndarray]:
    """Whatever the friction model (docs/cli.md): the torque by kind,
    `torque_rolling_Nmm`, `torque_sliding_Nmm`, `torque_drag_Nmm` (summing to `torque_Nmm`),
    and, with a speed, the heat by where it is made, `heat_inner_W`, `heat_outer_W`,
    `heat_ball_W` (summing to `heat_W`; `analytic.friction.pair.TorqueComponents`)."""
    out = dict(zip(FRICTION_SPLIT_TORQUE, (t.rolling_Nmm, t.sliding_Nmm, t.drag_Nmm)))
    if t.heat_W is not None:
        out.update(zip(FRICTION_SPLIT_HEAT, (t.heat_inner_W, t.heat_outer_W, t.heat_ball_W)))
    n = np.shape(t.torque_Nmm)
    return {k: np.broadcast_to(np.asarray(v, float), n) for k, v in out.items()}


#: the model-form interval's columns (`interval_columns`), after the friction split
INTERVAL_COLUMNS = ("torque_lo_Nmm", "torque_hi_Nmm", "heat_lo_W", "heat_hi_W")


def interval_columns(t) -> dict[str, np.ndarray]:
    """The friction law's model-form interval on the torque and the heat
    (`analytic.friction.interval.model_form_interval` of the result's regime and law; NaN where
    none can be stated; docs/cli.md "Model-form interval"); heat columns with a speed only."""
    from analytic.friction.interval import model_form_interval, regime_of
    law = "solid_film" if t.model == "solid_film" else t.viscous_model
    i = model_form_interval(regime_of(t.model, t.lubrication_method), law)
    n = np.shape(t.torque_Nmm)
    out = dict(zip(INTERVAL_COLUMNS[:2], i.apply(t.torque_Nmm)))
    if t.heat_W is not None:
        out.update(zip(INTERVAL_COLUMNS[2:], i.apply(t.heat_W)))
    return {k: np.broadcast_to(v, n) for k, v in out.items()}


def lame_column_names(layer_names: tuple[str, ...]) -> tuple[str, ...]:
    """The names of the Lamé neighbours' columns (`_lame_columns`), in their order, for an
    assembly with these sleeve / cartridge layers."""
    return ("fit_pressure_inner_lame_MPa", "fit_pressure_inner_lame_plane_strain_MPa",
            "fit_pressure_outer_lame_MPa", "fit_pressure_outer_lame_plane_strain_MPa",
            *(f"fit_pressure_{name}_lame_MPa" for name in layer_names),
            "raceway_u_r_inner_A_um", "raceway_u_r_inner_A_lame_um")


def _lame_columns(result: SimulationResult) -> dict[str, np.ndarray]:
    """The Lamé neighbours, and the FE's inner raceway displacement beside its Lamé value
    (named by `lame_column_names`)."""
    lm = result.lame
    values = (lm.fit_pressure_inner_MPa, lm.fit_pressure_inner_plane_strain_MPa,
              lm.fit_pressure_outer_MPa, lm.fit_pressure_outer_plane_strain_MPa,
              *(lm.layer_pressure_MPa[:, k] for k in range(len(lm.layer_names))),
              1e3 * result.fe.raceway_u_mm[:, 0], 1e3 * lm.raceway_u_r_inner_A_mm)
    return dict(zip(lame_column_names(result.layer_names), values, strict=True))


def _ball_columns(pair) -> dict[str, np.ndarray]:
    """Columns of the outer contact and of the ball's speed loads, present in every row:
    contact angle and load of the outer contact of each bearing (equal to the inner ones,
    `contact_angle_{J}_deg` and `ball_load_{J}_N`, with quasi-static balls), and the centrifugal
    force (N) and gyroscopic moment (N mm) on a ball of bearing A (0 with quasi-static balls)."""
    d = pair.dynamic
    if d is None:
        angle_o, load_o = pair.contact_angle_deg, pair.ball_load_N
        z = np.zeros(pair.preload_N.shape)
        fc, mg = z, z
    else:
        angle_o, load_o = d.contact_angle_outer_deg, d.load_outer_N
        fc, mg = d.centrifugal_force_N[0], d.gyroscopic_moment_Nmm[0]
    out = {f"contact_angle_outer_{J}_deg": angle_o[j] for j, J in enumerate(AB)}
    out.update({f"ball_load_outer_{J}_N": load_o[j] for j, J in enumerate(AB)})
    out["centrifugal_force_N"] = fc
    out["gyroscopic_moment_Nmm"] = mg
    return out


def _load_columns(pair) -> dict[str, np.ndarray]:
    """Columns of the pair under radial load and moment (`analytic.bearing.RadialLoadState`),
    present in every row: rotor radial displacement at the pair's mid-point (um) and tilt
    (mrad), each bearing's radial reaction (N) and its largest Hertz pressure over all balls
    (MPa). Rows without radial load and moment: zero displacement, tilt and reactions, and the
    axial state's pressures (every ball alike)."""
    r = pair.radial
    if r is None:
        n = pair.preload_N.shape[0]
        z = np.zeros(n)
        rho, tilt, Fr = z, z, np.zeros((2, n))
        p = np.maximum(pair.inner.p_max_MPa, pair.outer.p_max_MPa)
    else:
        rho, tilt, Fr, p = r.rho_mm, r.tilt_rad, r.radial_force_N, r.max_contact_pressure_MPa
    out = {"radial_displacement_um": 1e3 * rho, "tilt_mrad": 1e3 * tilt}
    for j, J in enumerate(AB):
        out[f"radial_force_{J}_N"] = Fr[j]
    for j, J in enumerate(AB):
        out[f"max_contact_pressure_{J}_MPa"] = p[j]
    return out
