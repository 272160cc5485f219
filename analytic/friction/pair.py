"""The friction route of a bearing pair: every friction law of `analytic.friction` on a
`bearing.PairState`, summed over both bearings, with the heat by where it is made
(`pair_torque` -> `TorqueComponents`). The one place the laws are chosen
(`options.FrictionOptions.viscous_model`, `shear_strength`); `simulate`, the transient
route, the thermal speeds and the diagnosis's friction rungs reach the laws through it.

Units: N, mm, rpm, mm^2/s; torques N*mm, heats W.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.friction.ehl_rolling import K_RANGE as EHL_K_RANGE
from analytic.friction.ehl_rolling import (GYRO_NOTE, CentrifugalFloor, EHLRollingTorque,
                                           centrifugal_force_N, ehl_rolling_bearing,
                                           gyroscopic_traction_ratio, spin_torque_bearing,
                                           spin_traction_coefficient)
from analytic.friction.options import FrictionOptions
from analytic.friction.palmgren import (coulomb_load_torque_Nmm, palmgren_load_torque_Nmm,
                                        palmgren_viscous_torque_Nmm)
from analytic.friction.ranges import RangeNote, RangeRows, combine, notes, range_rows
from analytic.friction.skf2004 import (DRAG_LEVEL_MAX_DM, NDM_LIMIT, constants_for,
                                       skf2004_torque)
from analytic.friction.solid_film import pressure_dependent_mu
from analytic.friction.starved import R_RANGE as STARVED_R_RANGE
from analytic.friction.minimal_oil import minimal_oil_bearing_ratio
from analytic.friction.starved import starvation_ratio, supply_layer_um
from analytic.hertz import ball_raceway_radii_mm
from analytic.lubrication import (ellipticity_hamrock_dowson, hamrock_dowson_film,
                                  reduced_modulus_MPa)
from analytic.torque import (RPM_TO_RAD_S, ContactInput, ContactTorques, ball_kinematics,
                             power_W, solid_film_torque_Nmm)


def contact_inputs(pair, j: int) -> tuple[ContactInput, ContactInput]:
    """Inner and outer `ContactInput` of bearing j (0 = A, 1 = B) of a `bearing.PairState`
    (ball load N, ellipse semi-axes mm, E(e), Rx mm); with quasi-dynamic balls
    (`pair.dynamic`) each contact at its own load."""
    d = pair.dynamic
    Q = (pair.ball_load_N[j], pair.ball_load_N[j]) if d is None else (d.load_inner_N[j],
                                                                      d.load_outer_N[j])
    return tuple(ContactInput(q, c.a_mm[j], c.b_mm[j], c.E_ell[j], c.Rx_mm[j])
                 for q, c in zip(Q, (pair.inner, pair.outer)))


def contact_angles_rad(pair, j: int):
    """(inner, outer) contact angle of bearing j of a `bearing.PairState`, rad; the outer one is
    None for quasi-static balls (equal to the inner one)."""
    d = pair.dynamic
    if d is None:
        return np.radians(pair.contact_angle_deg[j]), None
    return np.radians(d.contact_angle_inner_deg[j]), np.radians(d.contact_angle_outer_deg[j])


def ball_contact_inputs(radial, j: int) -> tuple[ContactInput, ContactInput]:
    """Inner and outer `ContactInput` of every ball of bearing j, (Z, N), from the combined-load
    state (`bearing.RadialLoadState`: ball_loads_N, ball_inner, ball_outer; with quasi-dynamic
    balls the outer contacts at their own loads, ball_loads_outer_N)."""
    Q_i = radial.ball_loads_N[j]
    Q_o = Q_i if radial.ball_loads_outer_N is None else radial.ball_loads_outer_N[j]
    return tuple(ContactInput(Q, c.a_mm[j], c.b_mm[j], c.E_ell[j], c.Rx_mm[j])
                 for Q, c in ((Q_i, radial.ball_inner), (Q_o, radial.ball_outer)))


@dataclass(frozen=True)
class TorqueComponents:
    """Friction torque of a bearing pair (`pair_torque`), N*mm, arrays (n,) over operating points.

    model: "solid_film" or "oil" (which of the component fields are set; the others are None).
    torque_Nmm: the pair's torque (bearing A + bearing B); torque_A_Nmm, torque_B_Nmm: per bearing.
    heat_W: dissipated power of the pair, W (`power_W`; None when no speed was given).
    Solid film: hysteresis_Nmm, differential_Nmm, spin_Nmm (each dissipation, both bearings,
    inner + outer contacts), inner_contacts_Nmm, outer_contacts_Nmm (every component of the
    inner or of the outer contacts, both bearings).
    Oil: load_Nmm (the load term, both bearings; with viscous_model "skf2004" SKF's sliding
    term), viscous_Nmm (the viscous term of `viscous_model`, both bearings), viscosity_mm2_s
    (the kinematic viscosity the viscous term used, mm^2/s).
    Every model: rolling_Nmm, sliding_Nmm, drag_Nmm (their sum is torque_Nmm: oil,
    the viscous term, the load term and the drag; solid film, the hysteresis, the differential
    slip + spin, 0) and with a speed the heat by where it is made, heat_inner_W (the inner
    contacts), heat_outer_W (the outer contacts), heat_ball_W (in the oil around the balls: the
    drag), summing to heat_W. A term without a location of its own (Palmgren's viscous and load
    terms, SKF's rolling and sliding terms) is shared equally by the inner and outer contacts,
    as `analytic.heat.pair_heat_W` shares the viscous heat.
    range_notes: the rows where the law left its source's range (`analytic.friction.ranges`;
    one warning line each through the command's warnings)."""
    model: str
    torque_Nmm: np.ndarray
    torque_A_Nmm: np.ndarray
    torque_B_Nmm: np.ndarray
    heat_W: np.ndarray | None = None
    hysteresis_Nmm: np.ndarray | None = None
    differential_Nmm: np.ndarray | None = None
    spin_Nmm: np.ndarray | None = None
    inner_contacts_Nmm: np.ndarray | None = None
    outer_contacts_Nmm: np.ndarray | None = None
    load_Nmm: np.ndarray | None = None
    viscous_Nmm: np.ndarray | None = None
    viscosity_mm2_s: np.ndarray | None = None
    rolling_Nmm: np.ndarray | None = None
    sliding_Nmm: np.ndarray | None = None
    drag_Nmm: np.ndarray | None = None
    heat_inner_W: np.ndarray | None = None
    heat_outer_W: np.ndarray | None = None
    heat_ball_W: np.ndarray | None = None
    viscous_model: str = "palmgren"
    range_notes: tuple[RangeNote, ...] = ()
    lubrication_method: str = ""


@dataclass(frozen=True)
class BearingContacts:
    """One bearing's contacts as the friction laws take them, arrays over operating points.

    per_ball False: a representative ball standing for all Z balls (arrays (n,)); True: every
    ball's own contacts (arrays (Z, n), one ball each, summed over the first axis).
    alpha_outer_rad None: the outer contact angle equals the inner one (quasi-static balls).
    axial_force_N, radial_force_N: the loads the bearing carries (N, (n,)), for the bearing-level
    laws (Palmgren's and SKF's load terms). outer_control: True where the outer raceway
    controls the ball (quasi-static balls: always; quasi-dynamic balls: their hypothesis), for
    the kinematics of `ehl_rolling`; gyroscopic_moment_Nmm: the quasi-dynamic balls' M_g per
    ball (N mm; None for quasi-static balls)."""
    inner: ContactInput
    outer: ContactInput
    alpha_inner_rad: np.ndarray
    alpha_outer_rad: np.ndarray | None
    axial_force_N: np.ndarray
    radial_force_N: np.ndarray | float = 0.0
    per_ball: bool = False
    outer_control: np.ndarray | bool = True
    gyroscopic_moment_Nmm: np.ndarray | None = None


def pair_bearing_contacts(pair, j: int) -> BearingContacts:
    """Bearing j (0 = A, 1 = B) of a `bearing.PairState` as its representative ball
    (`contact_inputs`, `contact_angles_rad`), with its axial force and its share of a radial
    load (0 without one)."""
    r, d = pair.radial, pair.dynamic
    Fr = 0.0 if r is None else np.abs(r.radial_force_N[j])
    dyn = {} if d is None else dict(outer_control=d.outer_control[j],
                                    gyroscopic_moment_Nmm=d.gyroscopic_moment_Nmm[j])
    return BearingContacts(*contact_inputs(pair, j), *contact_angles_rad(pair, j),
                           pair.axial_force_N[j], Fr, **dyn)


def single_bearing_contacts(st) -> BearingContacts:
    """Every ball's own contacts of one bearing in the state `st`
    (`analytic.bearing.single.SingleBearingState`, arrays (Z, n)): loads, Hertz ellipses and
    contact angles (the outer angle its own with quasi-dynamic balls); the axial force |F_z| and
    the radial force |(F_x, F_y)| the balls carry."""
    b = st.balls
    e_i, e_o = b.ellipse_inner, b.ellipse_outer
    inner = ContactInput(b.load_inner_N, e_i.a_mm, e_i.b_mm, e_i.E_ell, e_i.Rx_mm)
    outer = ContactInput(b.load_outer_N, e_o.a_mm, e_o.b_mm, e_o.E_ell, e_o.Rx_mm)
    dynamic = st.ball_model == "quasi_dynamic"
    dyn = {} if not dynamic else dict(
        outer_control=True if b.outer_control is None else b.outer_control,
        gyroscopic_moment_Nmm=b.gyroscopic_moment_Nmm)
    return BearingContacts(inner, outer, np.radians(b.contact_angle_inner_deg),
                           np.radians(b.contact_angle_outer_deg) if dynamic else None,
                           np.abs(b.loads[0]), np.hypot(b.loads[1], b.loads[2]), per_ball=True,
                           **dyn)


@dataclass(frozen=True)
class BearingFriction:
    """Friction of one bearing (`bearing_friction`), N*mm, arrays (n,) over operating points.
    load_Nmm: the load term (SKF: its sliding term; solid film: differential slip + spin),
    viscous_Nmm: the viscous term (SKF: its rolling term; solid film: hysteresis), drag_Nmm: the
    drag in the oil around the balls; total_Nmm = load + viscous + drag. heat_inner_W,
    heat_outer_W: heat a law computes at the contacts from their own speeds (`ehl_rolling`),
    else None. solid: the solid-film components (`analytic.torque.ContactTorques`, per ball
    where per_ball), else None. ranges: where the law left its source's range
    (`analytic.friction.ranges.RangeRows`, per row). spin_inner_Nmm, spin_outer_Nmm: the spin
    sliding of the inner and outer contacts (`ehl_rolling`; in total_Nmm beside the load and
    viscous terms), else None."""
    total_Nmm: np.ndarray
    load_Nmm: np.ndarray
    viscous_Nmm: np.ndarray
    drag_Nmm: np.ndarray
    heat_inner_W: np.ndarray | None = None
    heat_outer_W: np.ndarray | None = None
    solid: ContactTorques | None = None
    ranges: tuple[RangeRows, ...] = ()
    spin_inner_Nmm: np.ndarray | None = None
    spin_outer_Nmm: np.ndarray | None = None


def bearing_friction(g, c: BearingContacts, *, model: str = "solid_film", mu=0.02,
                     hysteresis_loss=0.0, speed_rpm=None, f0=0.0, nu_mm2_s=0.0, f1=None,
                     load_term: str = "coulomb", friction=None) -> BearingFriction:
    """Friction torque of one bearing from its contacts `c` (`BearingContacts`), N*mm: the
    one route of every law (the arguments as `pair_torque`'s, which sums this over the two
    bearings of a pair; `bearing` calls it on a single bearing's balls)."""
    fr = FrictionOptions() if friction is None else friction
    if model == "solid_film":
        t = _solid_film_bearing(g, c, mu, hysteresis_loss, fr)
        s = (lambda x: x.sum(axis=0)) if c.per_ball else (lambda x: x)
        rolling = s(t.hysteresis_inner_Nmm + t.hysteresis_outer_Nmm)
        sliding = s(t.differential_inner_Nmm + t.differential_outer_Nmm + t.spin_inner_Nmm
                    + t.spin_outer_Nmm)
        return BearingFriction(s(t.total_Nmm), sliding, rolling, np.zeros_like(rolling), solid=t)
    if model != "oil":
        raise ValueError(f"model must be 'solid_film' or 'oil', got {model!r}")
    return _oil_bearing(g, c, mu, speed_rpm, f0, nu_mm2_s, f1, load_term, fr)


def pair_torque(g, pair, *, model: str = "solid_film", mu=0.02, hysteresis_loss=0.0,
                speed_rpm=None, f0=0.0, nu_mm2_s=0.0, f1=None,
                load_term: str = "coulomb", friction=None) -> TorqueComponents:
    """Friction torque of a bearing pair from its `bearing.PairState`, vectorised, N*mm
    (`TorqueComponents`): `bearing_friction` of each bearing's representative ball, summed.

    model "solid_film": `solid_film_torque_Nmm` per bearing (mu: film friction coefficient,
      hysteresis_loss: alpha_h; with friction.shear_strength "pressure" each contact's own
      coefficient tau0 / p_mean + alpha, `analytic.friction.solid_film`, in place of mu); at
      points where the balls of a bearing carry unequal loads
      (radial load or tilt: `pair.radial`) the sum over every ball's own contacts and contact
      angle instead of Z times the representative ball; sets the hysteresis, differential and
      spin parts (both bearings, inner + outer), the inner- and outer-contact sums and the
      per-bearing totals.
    model "oil": load term per bearing (load_term "coulomb": mu F_a dm/2; "palmgren": f1 F_a dm;
      F_a = sum_k Q_k sin(alpha_k) the bearing's axial force, which under a radial load includes
      the axial component the radial load induces; Harris Vol. 2 gives P1 = F_a - 0.1 F_r for an
      angular-contact bearing, not applied here)
      plus the viscous term per bearing of friction.viscous_model: "palmgren" (f0, nu_mm2_s,
      speed_rpm), "starved" (Palmgren's times the starved-film ratio of the oil quantity,
      `analytic.friction.starved`), "ehl_rolling" (the EHL rolling resistance of each contact,
      `analytic.friction.ehl_rolling`); "skf2004" replaces both terms by SKF's rolling and
      sliding terms and adds its drag (`analytic.friction.skf2004`); sets the load and
      viscous terms (both bearings), the viscosity used and the per-bearing totals.
    With speed_rpm given, also heat_W (total dissipated power) and its split by location.
    g: `bearing.BearingGeometry`; friction: `analytic.friction.options.FrictionOptions`
    (default: Palmgren, constant shear strength).
    """
    fr = FrictionOptions() if friction is None else friction
    args = dict(model=model, mu=mu, hysteresis_loss=hysteresis_loss, speed_rpm=speed_rpm, f0=f0,
                nu_mm2_s=nu_mm2_s, f1=f1, load_term=load_term, friction=fr)
    if model == "solid_film":
        per, parts = _solid_film_pair(g, pair, args)
        ranges = ()
        split = dict(rolling_Nmm=parts["hysteresis_Nmm"],
                     sliding_Nmm=parts["differential_Nmm"] + parts["spin_Nmm"],
                     drag_Nmm=np.zeros_like(parts["spin_Nmm"]))
        located = (parts["inner_contacts_Nmm"], parts["outer_contacts_Nmm"], None)
    elif model == "oil":
        per, parts, located, ranges = _oil_pair(g, pair, args)
        parts["viscosity_mm2_s"] = nu_mm2_s
        sliding = parts["load_Nmm"] + parts.get("spin_Nmm", 0.0)   # ehl_rolling's spin
        split = dict(rolling_Nmm=parts["viscous_Nmm"], sliding_Nmm=sliding,
                     drag_Nmm=parts.pop("drag_Nmm"))
    else:
        raise ValueError(f"model must be 'solid_film' or 'oil', got {model!r}")
    total = per[0] + per[1]
    heat = None if speed_rpm is None else power_W(total, speed_rpm)
    if heat is not None:
        split.update(_located_heat_W(located, split["drag_Nmm"], speed_rpm))
    return TorqueComponents(model, total, per[0], per[1], heat, **parts, **split,
                            viscous_model=fr.viscous_model, range_notes=ranges,
                            lubrication_method=fr.lubrication_method)


def _located_heat_W(located, drag_Nmm, speed_rpm) -> dict:
    """heat_inner_W, heat_outer_W, heat_ball_W from the torques made at the inner and outer
    contacts (N*mm) and the drag (at the balls); a contact's heat given directly in W (the
    third entry of `located`: (inner_W, outer_W) added to them) where a model computes it from
    the contact speeds (`ehl_rolling`)."""
    inner, outer, direct = located
    q_in, q_out = power_W(inner, speed_rpm), power_W(outer, speed_rpm)
    if direct is not None:
        q_in, q_out = q_in + direct[0], q_out + direct[1]
    return dict(heat_inner_W=q_in, heat_outer_W=q_out, heat_ball_W=power_W(drag_Nmm, speed_rpm))


def _solid_film_bearing(g, c: BearingContacts, mu, hysteresis_loss, fr) -> ContactTorques:
    """`solid_film_torque_Nmm` of one bearing's contacts (Z times the representative ball, or
    one per ball where c.per_ball), each contact's coefficient by fr.shear_strength."""
    c_ring = (1.0 - g.ring.nu ** 2) / g.ring.E_MPa
    c_ball = (1.0 - g.ball.nu ** 2) / g.ball.E_MPa
    mu_i, mu_o = mu, None
    if fr.shear_strength == "pressure":
        mu_i, mu_o = (pressure_dependent_mu(fr.tau0_MPa, fr.alpha_shear, k.Q_N, k.a_mm, k.b_mm)
                      for k in (c.inner, c.outer))
    return solid_film_torque_Nmm(1 if c.per_ball else g.Z, g.Dw_mm, g.dm_mm, g.f_i, g.f_o,
                                 c.alpha_inner_rad, c.inner, c.outer, mu_i, hysteresis_loss,
                                 c_ring, c_ball, c.alpha_outer_rad, mu_o)


def _solid_film_pair(g, pair, args) -> tuple[list, dict]:
    """Per-bearing totals and the pair's solid-film components (`pair_torque`), N*mm."""
    hyst = diff = spin = inner = outer = 0.0
    per = []
    for j in range(2):
        c = bearing_friction(g, pair_bearing_contacts(pair, j), **args).solid
        r = pair.radial
        if r is not None and r.ball_inner is not None and np.any(r.unequal_balls):
            # balls with unequal loads: every ball's own contacts and kinematics, summed
            bin_, bout = ball_contact_inputs(r, j)
            a_o = (None if r.ball_contact_angles_outer_deg is None
                   else np.radians(r.ball_contact_angles_outer_deg[j]))
            balls = BearingContacts(bin_, bout, np.radians(r.ball_contact_angles_deg[j]), a_o,
                                    pair.axial_force_N[j], per_ball=True)
            c = c.where(r.unequal_balls, bearing_friction(g, balls, **args).solid)
        hyst = hyst + c.hysteresis_inner_Nmm + c.hysteresis_outer_Nmm
        diff = diff + c.differential_inner_Nmm + c.differential_outer_Nmm
        spin = spin + c.spin_inner_Nmm + c.spin_outer_Nmm
        inner = inner + c.hysteresis_inner_Nmm + c.differential_inner_Nmm + c.spin_inner_Nmm
        outer = outer + c.hysteresis_outer_Nmm + c.differential_outer_Nmm + c.spin_outer_Nmm
        per.append(c.total_Nmm)
    return per, dict(hysteresis_Nmm=hyst, differential_Nmm=diff, spin_Nmm=spin,
                     inner_contacts_Nmm=inner, outer_contacts_Nmm=outer)


def _oil_bearing(g, c: BearingContacts, mu, speed_rpm, f0, nu_mm2_s, f1, load_term,
                 fr) -> BearingFriction:
    """One oil-lubricated bearing (`bearing_friction`): SKF's three terms, or the load term of
    `load_term` plus the viscous term of fr.viscous_model."""
    n = 0.0 if speed_rpm is None else speed_rpm
    model = fr.viscous_model
    if model == "skf2004":
        t = skf2004_torque(fr.bore_mm, fr.outside_diameter_mm, c.radial_force_N,
                           c.axial_force_N, n, nu_mm2_s, oil_level_mm=fr.oil_level_mm,
                           **constants_for(fr.lubrication_method, fr.oil_family))
        ndm = np.abs(np.asarray(n, float)) * g.dm_mm * np.ones_like(t.total_Nmm)
        level = (fr.oil_level_mm / (0.5 * (fr.bore_mm + fr.outside_diameter_mm))
                 * np.ones_like(t.total_Nmm))
        ranges = (range_rows("skf2004", "n dm", f"n dm <= {NDM_LIMIT:.3g} mm/min, the end of the "
                             "catalogue's limiting speeds", ndm, ndm > NDM_LIMIT),
                  range_rows("skf2004", "oil level H / dm", f"H <= {DRAG_LEVEL_MAX_DM:g} dm, the "
                             "drag formula's; taken as that level", level,
                             level > DRAG_LEVEL_MAX_DM))
        return BearingFriction(t.total_Nmm, t.sliding_Nmm, t.rolling_Nmm, t.drag_Nmm,
                               ranges=ranges)
    visc = palmgren_viscous_torque_Nmm(f0, nu_mm2_s, n, g.dm_mm)
    q_in = q_out = s_in = s_out = None
    ranges = ()
    if model == "starved" and fr.oil_quantity_mg > 0:
        ratio, ranges = _starvation_ratio(g, c, n, fr)
        visc = visc * ratio
    elif model == "minimal_oil" and fr.oil_quantity_mg > 0:
        ratio, ranges = minimal_oil_bearing_ratio(g, c, n, fr)
        visc = visc * ratio
    elif model == "ehl_rolling":
        ti, to, qi, qo, ranges = _ehl_bearing(g, c, n, fr.eta_Pa_s, fr.alpha_per_Pa)
        visc = ti + to
        if speed_rpm is not None:
            q_in, q_out = qi, qo
        s_in, s_out, gyro = _ehl_spin(g, c, n, spin_traction_coefficient(fr.oil_family))
        ranges = ranges + gyro
    Fa = c.axial_force_N
    if load_term == "coulomb":
        m1 = coulomb_load_torque_Nmm(mu, Fa, 0.5 * g.dm_mm)
    elif load_term == "palmgren":
        m1 = palmgren_load_torque_Nmm(f1, Fa, g.dm_mm)
    else:
        raise ValueError(f"load_term must be 'coulomb' or 'palmgren', got {load_term!r}")
    total = m1 + visc
    if s_in is not None:
        total = total + s_in + s_out
    return BearingFriction(total, m1, visc * np.ones_like(total), np.zeros_like(total), q_in, q_out,
                           ranges=ranges, spin_inner_Nmm=s_in, spin_outer_Nmm=s_out)


def _oil_pair(g, pair, args) -> tuple[list, dict, tuple]:
    """Per-bearing totals, the pair's load, viscous and drag terms (`pair_torque`), N*mm, and
    where they are made: (torque at the inner contacts, at the outer contacts, heat computed at
    the contacts in W or None), and the notes of the rows outside the law's range. A term
    without a location of its own is shared equally by the inner and outer contacts."""
    a, b = (bearing_friction(g, pair_bearing_contacts(pair, j), **args) for j in (0, 1))
    load, viscous = a.load_Nmm + b.load_Nmm, a.viscous_Nmm + b.viscous_Nmm
    drag = a.drag_Nmm + b.drag_Nmm
    parts = dict(load_Nmm=load, viscous_Nmm=viscous, drag_Nmm=drag)
    s_in = s_out = 0.0
    if a.spin_inner_Nmm is not None:            # ehl_rolling: the spin sliding at each contact
        s_in, s_out = a.spin_inner_Nmm + b.spin_inner_Nmm, a.spin_outer_Nmm + b.spin_outer_Nmm
        parts["spin_Nmm"] = s_in + s_out
    if a.heat_inner_W is not None:              # ehl_rolling: its heat located at each contact
        located = (0.5 * load + s_in, 0.5 * load + s_out, (a.heat_inner_W + b.heat_inner_W,
                                                          a.heat_outer_W + b.heat_outer_W))
    else:                                       # no law but ehl_rolling has a spin term
        located = (0.5 * (load + viscous), 0.5 * (load + viscous), None)
    return ([a.total_Nmm, b.total_Nmm], parts, located, notes(combine(a.ranges, b.ranges)))


def _ehl_bearing(g, c: BearingContacts, speed_rpm, eta0_Pa_s, alpha_per_Pa):
    """EHL rolling resistance of one bearing's contacts (`analytic.friction.ehl_rolling`):
    (inner-ring torque of the inner contacts, of the outer contacts) N mm and (heat at the
    inner contacts, at the outer contacts) W, summed over the balls where c.per_ball, and the
    rows whose rolling contacts leave Hamrock-Dowson's ellipticity range (`RangeRows`). An
    unloaded outer contact rolls under the ball's centrifugal force (`CentrifugalFloor`)."""
    Ep = reduced_modulus_MPa(g.ring.E_MPa, g.ring.nu, g.ball.E_MPa, g.ball.nu)
    kin = ball_kinematics(g.dm_mm, g.Dw_mm, c.alpha_inner_rad, c.alpha_outer_rad,
                          c.outer_control)
    a_o = c.alpha_inner_rad if c.alpha_outer_rad is None else c.alpha_outer_rad
    Rx, Ry = ball_raceway_radii_mm(g.Dw_mm, g.dm_mm, np.degrees(a_o), g.f_o, "outer")
    omega_c = np.abs(np.asarray(speed_rpm, float)) * RPM_TO_RAD_S * kin.cage
    floor = CentrifugalFloor(centrifugal_force_N(g.ball.density_N_s2_mm4, g.Dw_mm, g.dm_mm,
                                                 omega_c), Rx, ellipticity_hamrock_dowson(Rx, Ry))
    (ti, to), (qi, qo) = ehl_rolling_bearing(1 if c.per_ball else g.Z, g.dm_mm, Ep, c.inner,
                                             c.outer, kin.roll_inner, kin.roll_outer, speed_rpm,
                                             eta0_Pa_s, alpha_per_Pa, floor)
    if c.per_ball:
        ti, to, qi, qo = (x.sum(axis=0) for x in (ti, to, qi, qo))
    ks, out = [], []
    with np.errstate(divide="ignore", invalid="ignore"):
        for k, fl in ((c.inner, None), (c.outer, floor)):
            Q = np.asarray(k.Q_N, float)
            kk = np.asarray(k.a_mm, float) / np.asarray(k.b_mm, float)
            rolls = Q > 0
            if fl is not None:         # an unloaded outer contact at the centrifugal load
                kk, rolls = np.where(rolls, kk, fl.k), rolls | (fl.Q_N > 0)
            kk = np.where(rolls, kk, 1.0) * np.ones_like(ti)
            ks.append(kk)
            out.append(rolls & ((kk < EHL_K_RANGE[0]) | (kk > EHL_K_RANGE[1])))
    ranges = (range_rows("ehl_rolling", "ellipticity k", f"{EHL_K_RANGE[0]:g} <= k <= "
                         f"{EHL_K_RANGE[1]:g}, Hamrock-Dowson's fits", np.stack(ks), np.stack(out)),)
    return ti, to, qi, qo, ranges


def _ehl_spin(g, c: BearingContacts, speed_rpm, mu):
    """Spin sliding of one bearing's contacts (`analytic.friction.ehl_rolling.spin_torque_bearing`
    with traction coefficient mu, the kinematics of `ball_kinematics` at the contacts' angles and
    raceway control): (inner contacts, outer contacts) inner-ring torque N mm, summed over the
    balls where c.per_ball, 0 at rest (speed_rpm 0: no entrainment, no EHL film whose traction
    mu bounds; the law's starting torque is its load term); and, with quasi-dynamic balls, the rows where the controlling
    contact's traction cannot hold the gyroscopic moment (`RangeRows`; `GYRO_NOTE`)."""
    kin = ball_kinematics(g.dm_mm, g.Dw_mm, c.alpha_inner_rad, c.alpha_outer_rad,
                          c.outer_control)
    si, so = spin_torque_bearing(1 if c.per_ball else g.Z, c.inner, c.outer, kin.spin_inner,
                                 kin.spin_outer, mu)
    if c.per_ball:
        si, so = si.sum(axis=0), so.sum(axis=0)
    turning = np.abs(np.asarray(speed_rpm, float)) > 0
    si, so = np.where(turning, si, 0.0), np.where(turning, so, 0.0)
    if c.gyroscopic_moment_Nmm is None:
        return si, so, ()
    Q_ctl = np.where(c.outer_control, c.outer.Q_N, c.inner.Q_N)
    r = gyroscopic_traction_ratio(c.gyroscopic_moment_Nmm, g.Dw_mm, Q_ctl)
    return si, so, (range_rows("ehl_rolling", "gyroscopic traction 2 M_g / (Dw Q)", GYRO_NOTE,
                               r, r > mu),)


def ehl_rolling_pair(g, pair, speed_rpm, eta0_Pa_s, alpha_per_Pa):
    """EHL rolling resistance of each contact of a pair (`analytic.friction.ehl_rolling`) on its
    `bearing.PairState` (quasi-dynamic balls: each contact at its own load and angle, the
    kinematics from both angles), every ball of a bearing at the representative ball's state (a
    radial load's ball-to-ball variation is not resolved here). g: `bearing.BearingGeometry`;
    speed_rpm: inner-ring speed (outer fixed); eta0_Pa_s: the oil's dynamic viscosity at the
    inlet (scalar or per point); alpha_per_Pa: its pressure-viscosity coefficient. Returns the
    `analytic.friction.ehl_rolling.EHLRollingTorque` (torques N mm, heats W)."""
    t_in = t_out = q_in = q_out = 0.0
    per = []
    for j in (0, 1):
        ti, to, qi, qo, _ = _ehl_bearing(g, pair_bearing_contacts(pair, j), speed_rpm,
                                         eta0_Pa_s, alpha_per_Pa)
        t_in, t_out, q_in, q_out = t_in + ti, t_out + to, q_in + qi, q_out + qo
        per.append(ti + to)
    return EHLRollingTorque(t_in, t_out, q_in, q_out, tuple(per))


def _starvation_ratio(g, c: BearingContacts, n_rpm, fr):
    """Mean over a bearing's inner and outer contacts (and over its balls where c.per_ball) of
    the starved-film ratio h / h_ff (`analytic.friction.starved`) of the oil quantity
    fr.oil_quantity_mg: the flooded central film h_ff by Hamrock-Dowson at each contact's load,
    ellipticity a/b and entrainment speed; and where the supply ratio is below its source's
    range (`RangeRows`)."""
    Ep = reduced_modulus_MPa(g.ring.E_MPa, g.ring.nu, g.ball.E_MPa, g.ball.nu)
    omega = np.abs(np.asarray(n_rpm, float)) * RPM_TO_RAD_S
    kin = ball_kinematics(g.dm_mm, g.Dw_mm, c.alpha_inner_rad, c.alpha_outer_rad)
    ratios, supply, low = [], [], []
    with np.errstate(divide="ignore", invalid="ignore"):
        for k, roll in ((c.inner, kin.roll_inner), (c.outer, kin.roll_outer)):
            u = omega * 0.5 * g.dm_mm * roll
            h_ff = hamrock_dowson_film(k.Rx_mm, k.Rx_mm, Ep, fr.eta_Pa_s, fr.alpha_per_Pa, u,
                                       k.Q_N, k=np.asarray(k.a_mm) / np.asarray(k.b_mm)).h_central_um
            h_oil = supply_layer_um(fr.oil_quantity_mg, fr.density_kg_m3, g.dm_mm, k.a_mm)
            # an unloaded contact (no ellipse) or a bearing at rest: no film to starve
            loaded = (np.asarray(k.Q_N) > 0) & (h_ff > 0) & np.isfinite(h_ff)
            ratios.append(np.where(loaded, starvation_ratio(h_oil, h_ff), 1.0))
            r = np.where(loaded, h_oil / h_ff, np.inf)
            supply.append(r)
            low.append(loaded & (r < STARVED_R_RANGE[0]))
    ratio = 0.5 * (ratios[0] + ratios[1])
    ranges = (range_rows("starved", "supply ratio h_oil/h_ff", f"r >= {STARVED_R_RANGE[0]:g}, "
                         "Chevalier et al. 1998", np.stack(supply), np.stack(low)),)
    return (ratio.mean(axis=0) if c.per_ball else ratio), ranges
