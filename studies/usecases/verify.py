"""`bearingfem verify`: the FE held against closed forms, and its mesh convergence.

Cases (`VerifyCase`, written per docs/cli.md "verify" by `VerifyCase.to_json`; `rel_error` =
|FE - closed form| / closed form):
- lame_fit: two-cylinder fits, FE mean fit pressure (from contact reactions) vs Lamé
  (analytic/lame.py). Equal lengths with free ends and a frictionless fit make the plane-stress
  Lamé solution exact in 3-D (sigma_r + sigma_theta is constant, so the axial strain is uniform);
  rollers on both ends make the plane-strain solution exact. So the only difference is
  discretisation.
- lame_multilayer: an assembly's own fits (`verify --assembly`, `assembly_fit_cases`): its
  shaft and inner ring, and its outer ring / sleeve / cartridge / housing as concentric cylinders
  of one length with its materials and mean fits, free ends, frictionless: FE vs the multi-layer
  plane-stress Lamé solution (exact there), one case per fit and temperature.
- lame_displacement: the ring's outer-surface radial displacement vs Lamé.
- lame_bounds: a short ring on a long shaft, FE against both plane-stress and plane-strain values.
- free_thermal: one material, uniform temperature: u_r = theta r, zero stress.
- rotating_fit: a shaft (solid or hollow) with a ring, both spinning at omega, frictionless fit:
  FE mean fit pressure (centrifugal body force rho omega^2 r, `fem.forms.centrifugal_load`) vs the
  rotating-disc Lamé closed form (analytic/lame.py, Timoshenko & Goodier §32); plane strain
  (rollers on both ends) is exact in 3-D, plane stress only for a thin disc (sigma_r + sigma_theta
  varies with r under rotation, so a free-ended cylinder has an axial strain that varies with r).
  Its inputs echo the lame_fit inputs plus `rho_inner_kg_m3`, `rho_outer_kg_m3` (x 1e-12 gives
  N s^2/mm^4) and `omega_rad_s`. With it: `rotating_displacement` (the ring's outer radius at
  speed), `rotating_free` (a free spinning hollow cylinder, no fit) and `fit_open_speed` (the
  speed at which the fit opens, `fem.loosening` on the FE vs `lame.fit_open_speed_rad_s`).
- mesh_convergence: the quantities that feed the bearing model on the seed 000 stack over four
  mesh levels; observed order and grid convergence index (Roache 1998, GCI with Fs = 1.25)
  (`ConvergenceCase` of `convergence_case`; the assembly report and the benchmarks read them).

Beside the cases (`verification.json` keys "mms" and "requirements"):
- mms: manufactured solutions (`fem.mms`) for the thermo-elastic operator with a two-material
  frictionless fit (a hollow and a solid shaft) and for steady conduction; per operator and
  norm the expected order of the P2 elements, the observed one (least squares over the three
  finest of MMS_LEVELS) and pass when they differ by at most MMS_ORDER_TOL (`MMSCase`).
- mms_transient: the manufactured solution of the transient conduction FE across a fit with a
  contact conductance (`fem.mms_transient`): the observed order in space (P2, L2: 3, BDF2 at a
  small step) and in time (backward Euler 1, BDF2 2, on one mesh), pass within the tolerance of
  tests/test_transient_mms.py (`TransientMMSCase`).
- requirements: the traceability table (`studies.usecases.requirements.trace`): every requirement,
  the tests tagged with it, the outcome of their last pytest run in this checkout.
"""
from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, replace
from typing import NamedTuple
from pathlib import Path

import numpy as np

from analytic import lame
from analytic.materials import get_material
from fem.model import build_model
from fem.post import element_stresses, fit_mean_pressures, theta_per_element
from fem.loosening import fit_open_omega2
from fem.solver import FitSolver, Superposition
from meshes.section import two_cylinder_section
from studies.usecases.report_tools import md_table
from studies.usecases.requirements import trace

TOLERANCE = 0.005          # every Lamé case within 0.5 % on the default mesh
REL_FLOOR_MPa = 1e-9
#: structured-mesh levels of the manufactured solutions (cells across the inner material: h = 5 mm
#: / n, 6 mm / n with the solid shaft; up to 134 000 DOF, a few seconds)
MMS_LEVELS = (8, 16, 32, 64)
#: an observed order passes within this of the element's order (P2: 3 in L2, 2 in energy)
MMS_ORDER_TOL = 0.2


class BoundsCheck(NamedTuple):
    """What a lame_bounds case adds: whether the FE lies between the two 2-D idealisations, and
    why it need not."""
    within_bounds: bool
    note: str


@dataclass(frozen=True)
class VerifyCase:
    """One closed-form comparison: name, kind ("lame_fit", "lame_multilayer", "lame_displacement", "lame_bounds",
    "free_thermal", "rotating_fit", "rotating_displacement", "rotating_free", "fit_open_speed"),
    the inputs that recompute the closed form (names and units of docs/cli.md "verify"), the FE and
    closed-form values by name, the relative error, and what lame_bounds adds (`bounds`)."""
    name: str
    kind: str
    inputs: dict
    fe: dict
    closed_form: dict
    rel_error: float
    bounds: BoundsCheck | None = None

    @property
    def passed(self) -> bool:
        """Within TOLERANCE, or (lame_bounds) between the two 2-D idealisations."""
        return bool(self.bounds.within_bounds) if self.kind == "lame_bounds" \
            else self.rel_error <= TOLERANCE

    def to_json(self) -> dict:
        return {"name": self.name, "kind": self.kind, "inputs": self.inputs, "fe": self.fe,
                "closed_form": self.closed_form, "rel_error": self.rel_error,
                **(self.bounds._asdict() if self.bounds is not None else {})}


@dataclass(frozen=True)
class VerifyRun:
    """Everything `run` wrote: the closed-form cases, the mesh-convergence cases
    (`ConvergenceCase`), the manufactured-solution studies and the traceability rows."""
    cases: list
    convergence: list
    mms: list
    requirements: list
    mms_transient: list = ()


@dataclass(frozen=True)
class MMSCase:
    """One manufactured-solution convergence study: the operator, the norm of the error, the
    element's order and the observed one over the levels (`fem.mms.MMSLevel`, relative errors)."""
    name: str
    operator: str
    norm: str                    # "L2" or "energy"
    expected_order: float
    observed_order: float
    levels: tuple

    @property
    def passed(self) -> bool:
        return abs(self.observed_order - self.expected_order) <= MMS_ORDER_TOL

    def to_json(self) -> dict:
        key = "l2_rel" if self.norm == "L2" else "energy_rel"
        return {"name": self.name, "operator": self.operator, "norm": self.norm,
                "expected_order": self.expected_order, "observed_order": self.observed_order,
                "pass": self.passed, "tolerance": MMS_ORDER_TOL,
                "levels": [{"h_mm": lv.h_mm, "dofs": lv.dofs, "rel_error": getattr(lv, key)}
                           for lv in self.levels]}


@dataclass(frozen=True)
class TransientMMSCase:
    """One convergence study of the transient conduction FE (`fem.mms_transient`): in space (the
    step `h` is N^-1/2, N the DOFs) or in time (the step is dt in s, the error the distance to
    the next step's solution); the expected and observed orders, and the tolerance on them."""
    name: str
    scheme: str                  # "backward_euler" or "bdf2"
    variable: str                # "space" or "time"
    expected_order: float
    observed_order: float
    tolerance: float
    steps: tuple
    rel_errors: tuple

    @property
    def passed(self) -> bool:
        return abs(self.observed_order - self.expected_order) <= self.tolerance

    def to_json(self) -> dict:
        step = "h" if self.variable == "space" else "dt_s"
        return {"name": self.name, "scheme": self.scheme, "variable": self.variable,
                "expected_order": self.expected_order, "observed_order": self.observed_order,
                "pass": self.passed, "tolerance": self.tolerance,
                "levels": [{step: float(x), "rel_error": float(e)}
                           for x, e in zip(self.steps, self.rel_errors)]}


#: tolerances on the transient orders (tests/test_transient_mms.py: unstructured meshes scatter
#: the error constant by ~10 % per level in space; pre-asymptotic drift at the largest step in time)
TRANSIENT_SPACE_TOL, TRANSIENT_TIME_TOL = 0.3, 0.15


def transient_mms_cases(space_factors=None, time_steps_s=None) -> list[TransientMMSCase]:
    """The transient conduction FE against its manufactured solution (`fem.mms_transient`, the
    levels of tests/test_transient_mms.py unless given): the space order (P2, L2: 3) and the
    time orders of backward Euler (1) and BDF2 (2)."""
    from fem import mms_transient as mt

    space_factors = space_factors or mt.SPACE_FACTORS
    time_steps_s = time_steps_s or mt.TIME_STEPS_S
    h, e = mt.space_levels(space_factors)
    out = [TransientMMSCase("transient_conduction_space_L2", "bdf2", "space", 3.0, mt.slope(h, e),
                            TRANSIENT_SPACE_TOL, tuple(h), tuple(e))]
    for scheme, order in (("backward_euler", 1.0), ("bdf2", 2.0)):
        dts, diffs, _ = mt.time_levels(scheme, time_steps_s)
        out.append(TransientMMSCase(f"transient_conduction_time_{scheme}", scheme, "time", order,
                                    mt.slope(dts, diffs), TRANSIENT_TIME_TOL, tuple(dts),
                                    tuple(diffs)))
    return out


def mms_cases(levels: tuple[int, ...] = MMS_LEVELS) -> list[MMSCase]:
    """The manufactured-solution studies of `fem.mms` (TC4 inside, 9Cr18 outside the fit): a
    hollow shaft in a ring (thermo-elastic and conduction) and a solid shaft (thermo-elastic,
    the axis inside the domain)."""
    from fem import mms

    box = mms.TwoMaterialBox()
    el = [mms.elastic_fit_level(mms.ElasticFitField(box), n)[0] for n in levels]
    ax = [mms.elastic_fit_level(mms.axis_field(), n)[0] for n in levels]
    th = [mms.conduction_level(mms.ConductionField(box), n) for n in levels]
    ops = (("thermoelastic_fit_TC4_9Cr18", "axisymmetric thermo-elasticity, two materials, closed "
            "frictionless fit (fem.forms, fem.solver)", el),
           ("thermoelastic_fit_solid_shaft", "the same with a solid shaft (the axis, u_r = 0, inside "
            "the domain)", ax),
           ("conduction_TC4_9Cr18", "steady axisymmetric conduction, two conductivities, perfect "
            "contact (fem.forms, fem.thermal)", th))
    return [MMSCase(f"{name}_{norm}", op, norm, order, mms.observed_order(lv, norm), tuple(lv))
            for name, op, lv in ops for norm, order in (("L2", 3.0), ("energy", 2.0))]


def _solve_two_cylinder(section, T_C: float, T_ref_C: float, interference_um: float):
    model = build_model(section)
    solver = FitSolver(model)
    theta = np.array([model.materials[p].thermal_strain(T_C, T_ref_C) for p in model.part_names])
    sol = solver.solve(model.unit_loads @ theta, [interference_um / 2000.0])
    p = float(fit_mean_pressures(model, solver.fit_of_pair, sol.force_N)[0, 0])
    return model, sol, theta, p


def lame_fit_case(name: str, r_inner_mm: float, r_fit_mm: float, r_outer_mm: float,
                  inner_material: str, outer_material: str, interference_um: float,
                  assumption: str = "plane_stress", T_C: float = 20.0, T_ref_C: float = 20.0,
                  length_mm: float = 10.0, mesh_factor: float = 1.0) -> list[VerifyCase]:
    """A two-cylinder fit: FE vs Lamé fit pressure and ring outer-surface displacement."""
    mi, mo = get_material(inner_material), get_material(outer_material)
    sec = two_cylinder_section(r_inner_mm, r_fit_mm, r_outer_mm, inner_material, outer_material,
                               length_mm, plane_strain=assumption == "plane_strain")
    sec = sec.scaled(mesh_factor)
    model, sol, theta, p_fe = _solve_two_cylinder(sec, T_C, T_ref_C, interference_um)
    eff = float(lame.interference_at_temperature_um(interference_um, 2 * r_fit_mm, mi, mo, T_C,
                                                    T_ref_C))
    common = dict(r_inner_mm=r_inner_mm, r_fit_mm=r_fit_mm, r_outer_mm=r_outer_mm,
                  E_inner_MPa=mi.E_MPa, nu_inner=mi.nu, E_outer_MPa=mo.E_MPa, nu_outer=mo.nu)
    p_cf = float(lame.fit_pressure_MPa(**common, interference_um=eff, assumption=assumption))
    inputs = dict(common, interference_um=eff, assumption=assumption,
                  inner_material=inner_material, outer_material=outer_material,
                  length_mm=length_mm, dofs=model.ndofs)
    if T_C != T_ref_C:
        inputs.update(T_C=T_C, T_ref_C=T_ref_C, interference_nominal_um=interference_um)
    # with rollers the thermal strain is not free axially: only isothermal plane-strain cases
    scale = max(p_cf, float(lame.fit_pressure_MPa(**common, interference_um=abs(eff) or 1.0,
                                                  assumption=assumption)))
    cases = [VerifyCase(name, "lame_fit", inputs, {"fit_pressure_MPa": p_fe},
                        {"fit_pressure_MPa": p_cf}, abs(p_fe - p_cf) / max(scale, REL_FLOOR_MPa))]
    P = model.probe_matrix(np.array([[r_outer_mm], [length_mm / 2]]))
    u_fe = float((P @ sol.u)[0])
    u_cf = float(lame.fit_displacement_mm(r_outer_mm, "outer", **common, interference_um=eff,
                                          assumption=assumption)) + mo.thermal_strain(T_C, T_ref_C) * r_outer_mm
    if abs(u_cf) > 0:
        cases.append(VerifyCase(name + "_ring_expansion", "lame_displacement",
                                dict(inputs, r_mm=r_outer_mm), {"u_r_um": 1e3 * u_fe},
                                {"u_r_um": 1e3 * u_cf}, abs(u_fe - u_cf) / abs(u_cf)))
    return cases


def rotating_fit_cases(name: str, r_inner_mm: float, r_fit_mm: float, r_outer_mm: float,
                       inner_material: str, outer_material: str, interference_um: float,
                       speed_rpm: float, assumption: str = "plane_strain", length_mm: float = 10.0,
                       mesh_factor: float = 1.0) -> list[VerifyCase]:
    """A two-cylinder fit spinning at speed_rpm: FE vs the rotating Lamé closed form (fit
    pressure, ring outer-radius displacement, fit-opening speed). Isothermal."""
    mi, mo = get_material(inner_material), get_material(outer_material)
    sec = two_cylinder_section(r_inner_mm, r_fit_mm, r_outer_mm, inner_material, outer_material,
                               length_mm, plane_strain=assumption == "plane_strain")
    model = build_model(sec.scaled(mesh_factor), rotating_parts=("shaft", "inner_ring_A"))
    solver = FitSolver(model)
    omega = 2.0 * math.pi * speed_rpm / 60.0
    delta = [interference_um / 2000.0]
    sol = solver.solve(omega ** 2 * model.spin_load, delta)
    p_fe = float(fit_mean_pressures(model, solver.fit_of_pair, sol.force_N)[0, 0])
    common = dict(r_inner_mm=r_inner_mm, r_fit_mm=r_fit_mm, r_outer_mm=r_outer_mm,
                  E_inner_MPa=mi.E_MPa, nu_inner=mi.nu, E_outer_MPa=mo.E_MPa, nu_outer=mo.nu)
    rho = dict(rho_inner_N_s2_mm4=mi.density_N_s2_mm4, rho_outer_N_s2_mm4=mo.density_N_s2_mm4)
    p_cf = float(lame.rotating_fit_pressure_MPa(**common, interference_um=interference_um, **rho,
                                                omega_rad_s=omega, assumption=assumption))
    inputs = dict(common, interference_um=interference_um, assumption=assumption,
                  rho_inner_kg_m3=mi.density_kg_m3, rho_outer_kg_m3=mo.density_kg_m3,
                  omega_rad_s=omega, speed_rpm=speed_rpm, inner_material=inner_material,
                  outer_material=outer_material, length_mm=length_mm, dofs=model.ndofs)
    cases = [VerifyCase(name, "rotating_fit", inputs, {"fit_pressure_MPa": p_fe},
                        {"fit_pressure_MPa": p_cf}, abs(p_fe - p_cf) / max(p_cf, REL_FLOOR_MPa))]
    P = model.probe_matrix(np.array([[r_outer_mm], [length_mm / 2]]))
    u_fe = float((P @ sol.u)[0])
    u_cf = float(lame.rotating_fit_displacement_mm(
        r_outer_mm, "outer", **common, interference_um=interference_um, **rho, omega_rad_s=omega,
        assumption=assumption))
    cases.append(VerifyCase(name + "_ring_expansion", "rotating_displacement",
                            dict(inputs, r_mm=r_outer_mm), {"u_r_um": 1e3 * u_fe},
                            {"u_r_um": 1e3 * u_cf}, abs(u_fe - u_cf) / abs(u_cf)))
    w2 = fit_open_omega2(Superposition(solver), np.zeros((1, len(model.part_names))),
                         np.array([delta]), 0, (100.0 * omega) ** 2)[0]
    w_cf = float(lame.fit_open_speed_rad_s(**common, interference_um=interference_um, **rho,
                                           assumption=assumption))
    to_rpm = 60.0 / (2.0 * math.pi)
    cases.append(VerifyCase(name + "_open_speed", "fit_open_speed", inputs,
                            {"fit_open_speed_rpm": to_rpm * math.sqrt(w2)},
                            {"fit_open_speed_rpm": to_rpm * w_cf}, abs(math.sqrt(w2) - w_cf) / w_cf))
    return cases


def rotating_free_case(material: str = "9Cr18", r_in_mm: float = 10.0, r_out_mm: float = 20.0,
                       speed_rpm: float = 30000.0, mesh_factor: float = 1.0) -> VerifyCase:
    """A free hollow cylinder (one material, the fit interface tied by zero interference and
    the same speed on both sides), plane strain: u_r at the outer radius vs T&G §32."""
    r_mid = 0.5 * (r_in_mm + r_out_mm)
    sec = two_cylinder_section(r_in_mm, r_mid, r_out_mm, material, material, 10.0,
                               plane_strain=True).scaled(mesh_factor)
    model = build_model(sec, contact="bonded", rotating_parts=("shaft", "inner_ring_A"))
    omega = 2.0 * math.pi * speed_rpm / 60.0
    sol = FitSolver(model).solve(omega ** 2 * model.spin_load, [0.0])
    m = get_material(material)
    u_fe = float((model.probe_matrix(np.array([[r_out_mm], [5.0]])) @ sol.u)[0])
    u_cf = float(lame.rotating_displacement_mm(r_out_mm, r_in_mm, r_out_mm, m.E_MPa, m.nu,
                                               m.density_N_s2_mm4, omega, "plane_strain"))
    return VerifyCase(f"free_rotating_cylinder_{material}", "rotating_free",
                      {"material": material, "r_inner_mm": r_in_mm, "r_outer_mm": r_out_mm,
                       "E_MPa": m.E_MPa, "nu": m.nu, "rho_kg_m3": m.density_kg_m3,
                       "omega_rad_s": omega, "speed_rpm": speed_rpm, "r_mm": r_out_mm,
                       "assumption": "plane_strain", "dofs": model.ndofs},
                      {"u_r_um": 1e3 * u_fe}, {"u_r_um": 1e3 * u_cf}, abs(u_fe - u_cf) / abs(u_cf))


def rotating_cases(mesh_factor: float = 1.0) -> list[VerifyCase]:
    """The rotating reference cases: a solid steel shaft and a hollow TC4 shaft with
    a 9Cr18 ring at 65..75 % of their fit-opening speed (plane strain: exact), the solid pair as
    a thin disc (1 mm on a 15 mm radius, plane stress: the 3-D correction is of order
    (length / radius)^2, measured 8e-5 on the ring displacement, 3e-4 at 2 mm), and a free
    spinning cylinder."""
    f = mesh_factor
    return (rotating_fit_cases("rotating_solid_52100_shaft_52100_ring", 0.0, 10.0, 15.0, "52100",
                               "52100", 10.0, 60000.0, mesh_factor=f)
            + rotating_fit_cases("rotating_thin_disc_52100_shaft_52100_ring", 0.0, 10.0, 15.0,
                                 "52100", "52100", 10.0, 60000.0, assumption="plane_stress",
                                 length_mm=1.0, mesh_factor=f)
            + rotating_fit_cases("rotating_hollow_TC4_shaft_9Cr18_ring", 12.5, 17.5, 18.9, "TC4",
                                 "9Cr18", 5.0, 30000.0, mesh_factor=f)
            + [rotating_free_case(mesh_factor=f)])


def short_ring_case(mesh_factor: float = 1.0) -> VerifyCase:
    """A 9Cr18 ring of length 4 mm on a 40 mm long solid 52100 shaft: FE between the bounds?"""
    r_f, r_o, L, Lr, d_um = 10.0, 14.0, 40.0, 4.0, 10.0
    sec = two_cylinder_section(0.0, r_f, r_o, "52100", "9Cr18", L, ring_length_mm=Lr).scaled(mesh_factor)
    model, sol, _, p_fe = _solve_two_cylinder(sec, 20.0, 20.0, d_um)
    mi, mo = get_material("52100"), get_material("9Cr18")
    common = dict(r_inner_mm=0.0, r_fit_mm=r_f, r_outer_mm=r_o, E_inner_MPa=mi.E_MPa,
                  nu_inner=mi.nu, E_outer_MPa=mo.E_MPa, nu_outer=mo.nu, interference_um=d_um)
    ps = float(lame.fit_pressure_MPa(**common, assumption="plane_stress"))
    pe = float(lame.fit_pressure_MPa(**common, assumption="plane_strain"))
    lo, hi = min(ps, pe), max(ps, pe)
    return VerifyCase(
        "short_ring_on_long_shaft", "lame_bounds",
        dict(common, ring_length_mm=Lr, shaft_length_mm=L, dofs=model.ndofs),
        {"fit_pressure_MPa": p_fe},
        {"fit_pressure_plane_stress_MPa": ps, "fit_pressure_plane_strain_MPa": pe},
        0.0 if lo <= p_fe <= hi else min(abs(p_fe - lo), abs(p_fe - hi)) / lo,
        BoundsCheck(bool(lo <= p_fe <= hi),
                    "a short ring sits on a shaft stiffened by its unloaded length on both sides, "
                    "so the FE pressure need not lie between the two 2-D idealisations"))


def free_thermal_case(material: str = "9Cr18", dT_K: float = 100.0,
                      mesh_factor: float = 1.0) -> VerifyCase:
    """One material, uniform dT: u_r = theta r at the outer radius and no stress."""
    sec = two_cylinder_section(5.0, 10.0, 15.0, material, material, 10.0).scaled(mesh_factor)
    model, sol, theta, p_fe = _solve_two_cylinder(sec, 20.0 + dT_K, 20.0, 0.0)
    P = model.probe_matrix(np.array([[15.0], [5.0]]))
    u_fe = float((P @ sol.u)[0])
    u_cf = float(theta[0]) * 15.0
    vm = element_stresses(model, sol.u, theta_per_element(model, theta))["von_mises_MPa"]
    return VerifyCase(f"free_thermal_{material}", "free_thermal",
                      {"material": material, "dT_K": dT_K, "r_mm": 15.0,
                       "alpha_per_K": get_material(material).alpha_per_K},
                      {"u_r_um": 1e3 * u_fe, "max_von_mises_MPa": float(vm.max()),
                       "fit_pressure_MPa": p_fe},
                      {"u_r_um": 1e3 * u_cf, "max_von_mises_MPa": 0.0}, abs(u_fe - u_cf) / abs(u_cf))


#: bounds on the order a three-level extrapolation uses: an observed order below 1 (values that
#: barely change, at round-off or mesh-noise level, or a pre-asymptotic level) would extrapolate
#: far beyond the data, one above 4 exceeds what P2 reaches even on smooth problems
ORDER_BOUNDS = (1.0, 4.0)


@dataclass(frozen=True)
class Richardson:
    """A three-level extrapolation (`richardson`): observed order, the order the extrapolation
    used, the extrapolated value, the fine level's GCI (relative) and whether the levels converge
    monotonically."""
    observed_order: float
    order_used: float
    extrapolated: float
    gci_fine: float
    monotone: bool


def richardson(f: list[float], ratio: float = 2.0) -> Richardson:
    """Observed order, extrapolated value and GCI of the three finest values f = [coarse, mid,
    fine] (Roache, Verification and Validation in Computational Science, 1998; Fs = 1.25).

    The extrapolation uses the observed order kept within ORDER_BOUNDS (`order_used`). Values that
    oscillate or do not converge are not extrapolated (the finest value stands) and get Roache's
    Fs = 3 on the larger change as their GCI; values equal on all levels are converged (GCI 0)."""
    f1, f2, f3 = f[-3:]
    e32, e21 = f2 - f1, f3 - f2
    nan = float("nan")
    scale = abs(f3) if f3 != 0 else nan
    if e21 == 0 and e32 == 0:
        return Richardson(nan, nan, f3, 0.0, True)
    if e32 != 0 and e21 / e32 >= 0:
        p = math.log(abs(e32 / e21)) / math.log(ratio) if e21 != 0 else math.inf
        pu = min(max(p, ORDER_BOUNDS[0]), ORDER_BOUNDS[1])
        return Richardson(p, pu, f3 + e21 / (ratio ** pu - 1),
                          1.25 * abs(e21) / scale / (ratio ** pu - 1), True)
    return Richardson(nan, nan, f3, 3.0 * max(abs(e21), abs(e32)) / scale, False)


@dataclass(frozen=True)
class ConvergenceLevel:
    """One mesh level of a convergence study: its level factor, element sizes (mm; the corner
    size only for an assembly's graded mesh), DOFs and the FE quantities by name."""
    factor: float
    size_mm: float
    fit_size_mm: float
    dofs: int
    values: dict
    corner_size_mm: float | None = None

    def to_json(self) -> dict:
        head = {"factor": self.factor, "size_mm": self.size_mm, "fit_size_mm": self.fit_size_mm}
        if self.corner_size_mm is not None:
            head.update(corner_size_mm=self.corner_size_mm)
        return {**head, "dofs": self.dofs, **self.values}


@dataclass(frozen=True)
class QuantityConvergence:
    """One quantity over the levels: its Richardson extrapolation, and with a closed form the
    exact value, each level's relative error against it and the order between levels."""
    richardson: Richardson
    exact: float | None = None
    rel_error_vs_exact: tuple = ()
    order_vs_exact: tuple = ()

    def to_json(self) -> dict:
        out = asdict(self.richardson)
        if self.exact is not None:
            out.update(exact=self.exact, rel_error_vs_exact=list(self.rel_error_vs_exact),
                       order_vs_exact=list(self.order_vs_exact))
        return out


@dataclass(frozen=True)
class MeshAssessment:
    """An assembly's mesh assessed (mesh_convergence_case): the level used, its errors against
    the Richardson values, the largest, the target the sizes were chosen for (None: all given),
    and the temperatures (C) and open fits of the study."""
    used_level: int
    errors: dict
    error_max: float
    target_error: float | None
    temperatures_C: tuple
    open_fits: tuple

    @property
    def within_target(self) -> bool | None:
        return None if self.target_error is None else bool(self.error_max <= self.target_error)


@dataclass(frozen=True)
class ConvergenceCase:
    """A mesh-convergence study (`convergence_case`): the levels, the convergence of every
    quantity, the first quantity's finest value against its exact or Richardson value, and for an
    assembly's own mesh its assessment. `to_json` is the "mesh_convergence" case of docs/cli.md."""
    name: str
    inputs: dict
    levels: tuple
    quantities: dict
    fe: dict
    closed_form: dict
    rel_error: float
    assessment: MeshAssessment | None = None

    @property
    def used(self) -> ConvergenceLevel:
        """The level assessed (an assembly's case)."""
        return self.levels[self.assessment.used_level]

    def to_json(self) -> dict:
        out = {"name": self.name, "kind": "mesh_convergence", "inputs": self.inputs,
               "levels": [lv.to_json() for lv in self.levels],
               "quantities": {q: r.to_json() for q, r in self.quantities.items()},
               "fe": self.fe, "closed_form": self.closed_form, "rel_error": self.rel_error}
        a = self.assessment
        if a is not None:
            out.update(used_level=a.used_level, errors=a.errors, error_max=a.error_max,
                       target_error=a.target_error, within_target=a.within_target)
        return out


def convergence_case(name: str, inputs: dict, levels: list[ConvergenceLevel],
                     exact: dict | None = None) -> ConvergenceCase:
    """Observed order and GCI of every quantity over the levels (refinement ratio 2)."""
    qs = list(levels[0].values)
    quantities = {}
    for q in qs:
        r = richardson([lv.values[q] for lv in levels])
        if exact and q in exact:
            err = [abs(lv.values[q] - exact[q]) / abs(exact[q]) for lv in levels]
            order = [math.log(err[i] / err[i + 1]) / math.log(2.0)
                     if err[i + 1] > 0 and err[i] > 0 else float("nan")
                     for i in range(len(err) - 1)]
            quantities[q] = QuantityConvergence(r, exact[q], tuple(err), tuple(order))
        else:
            quantities[q] = QuantityConvergence(r)
    q0 = qs[0]
    ref = exact[q0] if exact and q0 in exact else quantities[q0].richardson.extrapolated
    finest = levels[-1].values[q0]
    # closed form: the exact value, or the Richardson extrapolation
    return ConvergenceCase(name, dict(inputs, refinement_ratio=2.0), tuple(levels), quantities,
                           {q0: finest}, {q0: ref}, abs(finest - ref) / abs(ref))


def lame_convergence_case(factors=(4.0, 2.0, 1.0, 0.5), progress=None) -> ConvergenceCase:
    """Smooth reference: hollow TC4 shaft / 9Cr18 ring (plane stress exact), errors vs Lamé."""
    ri, rf, ro, d_um = 12.5, 17.5, 18.9, 5.0
    mi, mo = get_material("TC4"), get_material("9Cr18")
    common = dict(r_inner_mm=ri, r_fit_mm=rf, r_outer_mm=ro, E_inner_MPa=mi.E_MPa, nu_inner=mi.nu,
                  E_outer_MPa=mo.E_MPa, nu_outer=mo.nu, interference_um=d_um)
    exact = dict(fit_pressure_MPa=float(lame.fit_pressure_MPa(**common)),
                 ring_u_r_um=1e3 * float(lame.fit_displacement_mm(ro, "outer", **common)))
    base = two_cylinder_section(ri, rf, ro, "TC4", "9Cr18", 10.0, size_mm=1.0, fit_size_mm=0.5)
    levels = []
    for fac in factors:
        sec = base.scaled(fac)
        model, sol, _, p = _solve_two_cylinder(sec, 20.0, 20.0, d_um)
        u = float((model.probe_matrix(np.array([[ro], [5.0]])) @ sol.u)[0])
        levels.append(ConvergenceLevel(fac, sec.size_mm, sec.fit_size_mm, int(model.ndofs),
                                       dict(fit_pressure_MPa=p, ring_u_r_um=1e3 * u)))
        if progress:
            progress(f"  Lamé level {len(levels)}/{len(factors)}: {model.ndofs} DOF")
    return convergence_case("mesh_convergence_lame_TC4_9Cr18", dict(common, assumption="plane_stress"),
                            levels, exact)


def at_temperature(quantity: str, T_C: float) -> str:
    """The name of an assembly convergence quantity at one temperature (C), e.g.
    "groove_shift_dr_A_um at -40 C"."""
    return f"{quantity} at {T_C:g} C"


def mesh_convergence_case(assembly, factors=(2.0, 1.0, 0.5), used: int = 1,
                          temperatures_C=None, progress=None) -> ConvergenceCase:
    """The discretisation error of an assembly's mesh: the FE quantities that feed the bearing
    model on the levels `factors` of its mesh family (`Section.scaled`, coarse to fine; the
    Richardson value from the three finest), at the coldest and hottest temperature of
    `[operating]` (or `temperatures_C`) with the mean fits, through the pipeline.

    Quantities: the mean pressure of every fit closed on all levels (MPa) and the groove-centre
    shifts dr, dz of both bearings (um). Its `assessment.errors`: those of level `used` (the mesh
    assessed) against the Richardson values (studies/model/mesh_size.py): a fit pressure relative
    to its value, a bearing's groove shift as the length of the (dr, dz) error over the length of
    (dr, dz). `error_max` is the largest, `target_error` the one the sizes were chosen for (None:
    all sizes given). The default levels x2, x1, x0.5 assess the assembly's own mesh at a third
    of the cost of x1, x0.5, x0.25 (which the tests use: a reference from finer meshes only)."""
    from studies.model.inputs import baseline_inputs
    from studies.model.mesh_size import mesh_sizes
    from studies.model.pipeline import Pipeline

    op = assembly.operating
    temps = tuple(temperatures_C) if temperatures_C is not None else (op.T_min_C, op.T_max_C)
    T = np.array(temps, float)
    levels = []
    for fac in factors:
        pl = Pipeline.shared(assembly, mesh_factor=fac)
        inp = baseline_inputs(dict(T_ambient_C=T), T.size, assembly.T_ref_C,
                              assembly.preload.assembled_N, assembly.lubrication.speed_rpm)
        fe = pl.fe(inp)
        sec = pl.section
        values = {}
        for i, Tc in enumerate(temps):
            for k, fit in enumerate(sec.fits):
                name = fit.name.replace("fit_", "fit_pressure_") + "_MPa"
                values[at_temperature(name, Tc)] = float(fe.fit_pressure_MPa[i, k])
            for j, J in enumerate("AB"):
                values[at_temperature(f"groove_shift_dr_{J}_um", Tc)] = 1e3 * float(fe.dr_mm[j, i])
                values[at_temperature(f"groove_shift_dz_{J}_um", Tc)] = 1e3 * float(fe.dz_mm[j, i])
        levels.append(ConvergenceLevel(fac, sec.size_mm, sec.fit_size_mm, int(pl.ndofs), values,
                                       sec.corner_size_mm))
        if progress:
            progress(f"  {assembly.name} level {len(levels)}/{len(factors)}: {pl.ndofs} DOF")
    open_fits = [q for q in levels[0].values if q.startswith("fit_pressure")
                 and any(lv.values[q] <= 0 for lv in levels)]
    for lv in levels:                 # an open fit has no pressure to converge
        for q in open_fits:
            del lv.values[q]
    case = convergence_case(f"mesh_convergence_{assembly.name}",
                            dict(assembly=assembly.name, temperatures_C=list(temps),
                                 open_fits=open_fits), levels)
    errors = _level_errors(case, used)
    return replace(case, assessment=MeshAssessment(used, errors, max(errors.values()),
                                                   mesh_sizes(assembly).target_error, temps,
                                                   tuple(open_fits)))


def _level_errors(case: ConvergenceCase, level: int, per_quantity: bool = False) -> dict[str, float]:
    """Relative errors of one level against the Richardson values (see mesh_convergence_case):
    per fit pressure and per bearing's groove-shift vector, or (`per_quantity`) per quantity,
    a groove-shift component relative to the length of its bearing's shift."""
    q, lv = case.quantities, case.levels[level].values
    out = {}
    for name, r in q.items():
        if name.startswith("fit_pressure"):
            ext = r.richardson.extrapolated
            out[name] = abs(lv[name] - ext) / abs(ext)
        elif name.startswith("groove_shift_dr_"):
            dz = name.replace("_dr_", "_dz_")
            ref = (r.richardson.extrapolated, q[dz].richardson.extrapolated)
            err = (lv[name] - ref[0], lv[dz] - ref[1])
            length = math.hypot(*ref)
            if per_quantity:
                out[name], out[dz] = abs(err[0]) / length, abs(err[1]) / length
            else:
                out[name.replace("_dr_", "_")] = math.hypot(*err) / length
    return out


def discretisation_lines(case: ConvergenceCase) -> list[str]:
    """Markdown of an assembly's mesh_convergence_case: the sizes and where they come from, the
    target and the error achieved, and the table per quantity (report and verify)."""
    a = case.assessment
    used = case.used
    target = a.target_error
    worst = max(a.errors, key=a.errors.get)
    factors = ", ".join(f"x{lv.factor / used.factor:g}" for lv in case.levels)
    source = (f"chosen for a target error of {100 * target:g} % (`[mesh] target_error`; "
              "studies/model/mesh_size.py)" if target is not None else "all given in `[mesh]`")
    verdict = ("no target (explicit sizes)" if target is None else
               f"{'within' if a.within_target else 'NOT within'} the {100 * target:g} % target")
    rows = _level_errors(case, a.used_level, per_quantity=True)
    return [f"Element sizes of the mesh used: {used.size_mm:.4g} mm in the bulk, "
            f"{used.fit_size_mm:.4g} mm along fits and raceways, {used.corner_size_mm:.4g} mm "
            f"where fits and clamped faces end ({used.dofs} DOF), {source}.", "",
            f"The same FE at {' and '.join(f'{t:g} C' for t in a.temperatures_C)} "
            f"(mean fits) on the meshes {factors} of it; observed order and grid convergence index "
            "of the finest (Roache 1998, Fs = 1.25; the extrapolation uses the order kept within "
            f"{ORDER_BOUNDS[0]:g}..{ORDER_BOUNDS[1]:g}). Error of a fit pressure: relative to its "
            "Richardson value; of a groove-centre shift: relative to the length of its bearing's "
            "shift (dr, dz).", "",
            f"**Achieved: {100 * a.error_max:.2g} % ({worst}), {verdict}.**"
            + (f" Open fits (no pressure to converge): {', '.join(a.open_fits)}."
               if a.open_fits else ""), "",
            md_table(["quantity", "observed order", "Richardson value", "GCI (finest)",
                      "error of the mesh used"],
                     [[q, v.richardson.observed_order, v.richardson.extrapolated,
                       f"{v.richardson.gci_fine:.2e}", f"{rows[q]:.2e}"]
                      for q, v in case.quantities.items()]), ""]


def lame_cases(mesh_factor: float = 1.0) -> list[VerifyCase]:
    """The Lamé reference cases (each within `TOLERANCE` of the closed form)."""
    f = mesh_factor
    cases = []
    cases += lame_fit_case("solid_steel_shaft_steel_ring", 0.0, 10.0, 15.0, "52100", "52100", 10.0,
                           mesh_factor=f)
    cases += lame_fit_case("solid_steel_shaft_steel_ring_plane_strain", 0.0, 10.0, 15.0, "52100",
                           "52100", 10.0, assumption="plane_strain", mesh_factor=f)
    cases += lame_fit_case("hollow_TC4_shaft_9Cr18_inner_ring", 12.5, 17.5, 18.9, "TC4", "9Cr18",
                           5.0, mesh_factor=f)
    cases += lame_fit_case("9Cr18_outer_ring_in_TC4_housing", 22.1, 23.5, 30.0, "9Cr18", "TC4",
                           5.0, mesh_factor=f)
    cases += lame_fit_case("clearance_fit_9Cr18_ring_TC4_housing", 22.1, 23.5, 30.0, "9Cr18",
                           "TC4", -1.5, mesh_factor=f)
    for T in (-60.0, 80.0):
        cases += lame_fit_case(f"TC4_shaft_9Cr18_ring_at_{T:g}C", 12.5, 17.5, 18.9, "TC4", "9Cr18",
                               5.0, T_C=T, mesh_factor=f)
        cases += lame_fit_case(f"9Cr18_ring_TC4_housing_clearance_at_{T:g}C", 22.1, 23.5, 30.0,
                               "9Cr18", "TC4", -1.5, T_C=T, mesh_factor=f)
    cases.append(short_ring_case(mesh_factor=f))
    cases.append(free_thermal_case(mesh_factor=f))
    return cases + rotating_cases(mesh_factor=f)


def concentric_fit_case(name: str, radii_mm, parts: tuple[str, ...], materials, fit_keys,
                        interference_um, T_C: float, T_ref_C: float, length_mm: float,
                        mesh_factor: float = 1.0) -> list[VerifyCase]:
    """N concentric cylinders of one length (parts inside out, `materials` their
    `analytic.materials.Material`s, radii N+1), frictionless fits of the given diametral
    interferences (N-1, at T_ref) on the N-1 interfaces, free ends, every part at T_C: FE mean
    fit pressures vs the multi-layer plane-stress Lamé solution (`lame.multilayer_pressures_MPa`,
    exact here: sigma_r + sigma_theta is constant per layer and the layers slide axially), one
    case per fit (`fit_keys`: the fit each interface is, e.g. "inner", "outer", "sleeve").
    The Lamé interference of an interface: its fit plus the free thermal mismatch of its two
    layers, (theta_in - theta_out) x the diameter."""
    from meshes.section import Fit, Rect, Section, Split

    r, L = [float(x) for x in radii_mm], float(length_mm)
    rects = tuple(Rect(p, r[k], r[k + 1], 0.0, L, m.name) for k, (p, m) in enumerate(zip(parts, materials)))
    splits = tuple(Split(f"s{k}", "r", r[k + 1], 0.0, L, parts[:k + 1], parts[k + 1:])
                   for k in range(len(parts) - 1))
    fits = tuple(Fit(f"fit_{key}", parts[k], parts[k + 1], r[k + 1], 0.0, L, key)
                 for k, key in enumerate(fit_keys))
    h = (r[-1] - r[0]) / 16
    sec = Section(rects, splits, fits, (), tuple((f.r_mm, 0.0, f.r_mm, L) for f in fits),
                  {parts[0]: (r[0], L / 2)}, h, h / 2).scaled(mesh_factor)
    model = build_model(sec, materials=dict(zip(parts, materials)))
    solver = FitSolver(model)
    theta = np.array([m.thermal_strain(T_C, T_ref_C) for m in materials])
    d_um = np.asarray(interference_um, float)
    sol = solver.solve(model.unit_loads @ theta, d_um / 2000.0)
    p_fe = fit_mean_pressures(model, solver.fit_of_pair, sol.force_N)[0]
    eff = d_um + (theta[:-1] - theta[1:]) * 2.0 * np.asarray(r[1:-1]) * 1e3
    E, nu = [m.E_MPa for m in materials], [m.nu for m in materials]
    p_cf = lame.multilayer_pressures_MPa(r, E, nu, eff[None, :])[0]
    # the scale of a pressure error: the largest pressure of the case, or of the same stack with
    # every interface closed by its |interference| (an open case has zero pressures)
    scale = max(float(np.max(p_cf)),
                float(np.max(lame.multilayer_pressures_MPa(r, E, nu, np.abs(eff)[None, :]))),
                REL_FLOOR_MPa)
    inputs = dict(radii_mm=r, parts=list(parts), materials=[m.name for m in materials],
                  E_MPa=E, nu=nu, cte_per_K=[m.alpha_per_K for m in materials],
                  interference_nominal_um=[float(v) for v in d_um],
                  interference_um=[float(v) for v in eff], T_C=T_C, T_ref_C=T_ref_C,
                  length_mm=L, assumption="plane_stress", dofs=model.ndofs)
    return [VerifyCase(f"{name}_{key}_fit", "lame_multilayer", dict(inputs, fit=key),
                       {"fit_pressure_MPa": float(p_fe[k])}, {"fit_pressure_MPa": float(p_cf[k])},
                       abs(float(p_fe[k]) - float(p_cf[k])) / scale)
            for k, key in enumerate(fit_keys)]


def assembly_fit_cases(asm, mesh_factor: float = 1.0) -> list[VerifyCase]:
    """The Lamé cross-check on an assembly's own fits and materials (`verify --assembly`): at its
    coldest, reference and hottest `[operating]` temperature with its mean fits
    (`Assembly.mean_fit_um`, every part at the one temperature), (1) the inner fit as shaft
    (bore to seat) and inner ring (rectangular section to its outer diameter), (2) the outer side
    as the concentric outer ring / sleeve / cartridge / housing (to its outer diameter): every
    fit of the assembly, FE against Lamé (`concentric_fit_case`). Each stack is as long as a
    bearing is wide, free ended, its fits frictionless: the idealisation in which Lamé is exact,
    so the comparison checks the FE with the assembly's materials, sizes and fits, not the
    stack's shoulders and clamps (those the report's Lamé neighbours show)."""
    a, b = asm, asm.bearing
    op = a.operating
    mat = a.material
    inner = ((a.shaft.bore_diameter_mm / 2, a.shaft.seat_diameter_mm / 2,
              b.inner_ring_outer_diameter_mm / 2), ("shaft", "inner_ring_A"),
             (mat("shaft"), mat("inner_ring")), ("inner",), (a.mean_fit_um("inner"),))
    layers = [n for n, _ in a.layers()]
    radii = [b.outer_ring_inner_diameter_mm / 2, a.outer_seat_diameter_mm / 2]
    for _, layer in a.layers():
        radii.append(radii[-1] + layer.radial_thickness_mm)
    radii.append(a.housing.outer_diameter_mm / 2)
    outer = (tuple(radii), ("outer_ring_A", *layers, "housing"),
             (mat("outer_ring"), *(mat(n) for n in layers), mat("housing")),
             ("outer", *layers), (a.mean_fit_um("outer"), *(a.mean_fit_um(n) for n in layers)))
    cases = []
    for T in sorted({op.T_min_C, a.T_ref_C, op.T_max_C}):
        for side, (r, parts, mats, keys, d) in (("inner", inner), ("outer", outer)):
            cases += concentric_fit_case(f"assembly_{a.name}_at_{T:g}C", r, parts, mats, keys, d,
                                         T, a.T_ref_C, b.width_mm, mesh_factor)
    return cases


def write_verification(out_dir: Path, cases: list[VerifyCase], plot_path: Path | None,
                       mms: list[MMSCase] = (), requirements=(), convergence: list[ConvergenceCase] = (),
                       mms_transient: list[TransientMMSCase] = ()) -> None:
    """verification.json and verification.md (the tables a reviewer reads): the closed-form
    cases, then the mesh-convergence ones (`ConvergenceCase`) under "cases";
    `requirements`: `studies.usecases.requirements.RequirementTrace` rows. The one writer of both."""
    (out_dir / "verification.json").write_text(json.dumps(
        {"cases": [c.to_json() for c in cases] + [c.to_json() for c in convergence],
         "mms": [m.to_json() for m in mms],
         "mms_transient": [m.to_json() for m in mms_transient],
         "requirements": [r.to_json() for r in requirements]}, indent=2, default=float))
    lines = ["# bearingfem verification", "",
             "FE (axisymmetric P2, exact contact, fit pressure from contact reactions) against closed "
             "forms. Tolerance for every Lamé case: 0.5 %.", "",
             "| case | kind | FE | closed form | rel. error | pass |", "|---|---|---|---|---|---|"]
    for c in cases:
        fe = ", ".join(f"{k}={v:.6g}" for k, v in c.fe.items())
        cf = ", ".join(f"{k}={v:.6g}" for k, v in c.closed_form.items())
        lines.append(f"| {c.name} | {c.kind} | {fe} | {cf} | {c.rel_error:.2e} | "
                     f"{'yes' if c.passed else 'NO'} |")
    for c in convergence:
        qs = list(c.quantities)
        lines += ["", f"## Mesh convergence: {c.name}", "",
                  "| level | size (mm) | fit size (mm) | DOF | " + " | ".join(qs) + " |",
                  "|---" * (4 + len(qs)) + "|"]
        for i, lv in enumerate(c.levels):
            lines.append(f"| {i + 1} | {lv.size_mm:.3g} | {lv.fit_size_mm:.3g} | {lv.dofs} | "
                         + " | ".join(f"{lv.values[q]:.10g}" for q in qs) + " |")
        if c.assessment is not None:   # an assembly's own mesh: target and error achieved
            lines += [""] + discretisation_lines(c)
            continue
        lines += ["", "| quantity | observed order | Richardson extrapolation | GCI (fine) | "
                  "order vs exact |", "|---|---|---|---|---|"]
        for q, r in c.quantities.items():
            ex = ", ".join(f"{o:.2f}" for o in r.order_vs_exact) or "-"
            rr = r.richardson
            lines.append(f"| {q} | {rr.observed_order:.2f} | {rr.extrapolated:.10g} | "
                         f"{rr.gci_fine:.2e} | {ex} |")
    lines += ["", "P2 elements converge at order 2 in the energy norm and up to order 4 for "
              "reaction-based quantities on smooth problems (the Lamé case). In the assembled stack "
              "the ends of each fit and of each clamped face are stress singularities: uniform "
              "refinement converges there at order about 1 only, so the stack's mesh is graded "
              "towards those corners and its corner size refined as the square of the level "
              "factor; the family then converges at order 1.2..2 (studies/model/mesh_size.py)."]
    if plot_path is not None:
        lines += ["", f"![mesh convergence]({plot_path.name})"]
    for c in (c for c in cases if c.kind == "lame_bounds"):
        lines += ["", f"Short ring: FE {c.fe['fit_pressure_MPa']:.4g} MPa, plane stress "
                  f"{c.closed_form['fit_pressure_plane_stress_MPa']:.4g}, plane strain "
                  f"{c.closed_form['fit_pressure_plane_strain_MPa']:.4g}: "
                  f"{'between the bounds' if c.bounds.within_bounds else 'outside the bounds'}. {c.bounds.note}."]
    lines += mms_lines(mms) + transient_mms_lines(mms_transient) + requirement_lines(requirements)
    (out_dir / "verification.md").write_text("\n".join(lines) + "\n")


def mms_lines(mms: list[MMSCase]) -> list[str]:
    """Markdown: the manufactured-solution table (expected vs observed order, pass/fail)."""
    if not mms:
        return []
    rows = [[m.name, m.operator, m.norm, f"{m.expected_order:g}", f"{m.observed_order:.3f}",
             ", ".join(f"{(lv.l2_rel if m.norm == 'L2' else lv.energy_rel):.2e}" for lv in m.levels),
             "PASS" if m.passed else "FAIL"] for m in mms]
    h = ", ".join(f"{lv.h_mm:g}" for lv in mms[0].levels)
    return ["", "## Manufactured solutions (code verification)", "",
            "Fields in sin/cos/exp of r and z with the source terms that make them exact (fem/mms.py), "
            "two materials across a fit (TC4 inside, 9Cr18 outside: E, nu, alpha, k differ); the "
            "elastic field has a closed frictionless fit (u_r jumps by the interference, zero shear, "
            "continuous compressive normal stress, axial slip), the thermal one perfect contact. "
            f"Structured meshes, h = {h} mm (x 1.2 for the solid shaft); relative errors; observed "
            "order = least-squares slope over "
            f"the three finest levels; pass within {MMS_ORDER_TOL:g} of the P2 order.", "",
            md_table(["case", "operator", "norm", "expected order", "observed order",
                      "relative errors", "result"], rows)]


def transient_mms_lines(cases: list[TransientMMSCase]) -> list[str]:
    """Markdown: the transient manufactured solution's orders in space and time."""
    if not cases:
        return []
    rows = [[m.name, m.scheme, m.variable, f"{m.expected_order:g}", f"{m.observed_order:.3f}",
             ", ".join(f"{x:.3g}" for x in m.steps), ", ".join(f"{e:.2e}" for e in m.rel_errors),
             f"{'PASS' if m.passed else 'FAIL'} (within {m.tolerance:g})"] for m in cases]
    return ["", "## Manufactured solution of the transient conduction (code verification)", "",
            "The transient axisymmetric heat equation across a TC4 / 9Cr18 fit with a finite "
            "contact conductance, T = cos(pi z / L) (2 + sin(omega t)) (A_i + sin(pi r / 10) / k_i), "
            "its source applied at every step (fem/mms_transient.py). Space: BDF2 at dt = 0.02 s, "
            "three gmsh levels, h = N^-1/2 (N the DOFs), relative L2 error at t = 1 s. Time: one "
            "mesh, the error of step dt is the distance of its solution to the next smaller "
            "step's at t = 4 s (the spatial error cancels).", "",
            md_table(["case", "scheme", "in", "expected order", "observed order", "steps",
                      "relative errors", "result"], rows)]


def requirement_lines(requirements) -> list[str]:
    """Markdown: the traceability table requirement -> tests -> last result."""
    if not requirements:
        return []
    rows = [[r.id, r.text, "<br>".join(f"`{t}`" for t in r.tests) or "(none)", r.result]
            for r in requirements]
    return ["", "## Requirements traceability", "",
            "Each requirement, the tests tagged with it (`@pytest.mark.requirement`), and the result "
            "of their last pytest run in this checkout (recorded by tests/conftest.py; \"not run\" "
            "when none of its tests has run here).", "",
            md_table(["requirement", "statement", "tests", "last result"], rows)]


def plot_convergence(path: Path, cases: list[ConvergenceCase]) -> Path:
    """Relative error (vs exact, or vs the Richardson value) against element size, log-log."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(cases), figsize=(5.5 * len(cases), 4.5), squeeze=False)
    for ax, case in zip(axes[0], cases):
        h = np.array([lv.fit_size_mm for lv in case.levels])
        if case.assessment is not None:   # an assembly's mesh: its errors as the target counts them
            _plot_assembly_errors(ax, case, h)
            continue
        for q, r in case.quantities.items():
            vals = np.array([lv.values[q] for lv in case.levels])
            if r.exact is not None:
                err, lab, h_q = np.abs(vals - r.exact) / abs(r.exact), "vs exact", h
            else:
                ext = r.richardson.extrapolated
                err, lab = np.abs(vals - ext) / abs(ext), "vs Richardson"
                err, h_q = err[:-1], h[:-1]
            ok = err > 0
            if ok.any():
                ax.loglog(h_q[ok], err[ok], "o-",
                          label=f"{q} {lab} (p = {r.richardson.observed_order:.2f})")
        for order, style in ((2, "k--"), (4, "k:")):
            y0 = ax.get_ylim()[1] if ax.lines else 1.0
            ax.loglog(h, y0 * (h / h[0]) ** order, style, lw=0.8, label=f"slope {order}")
        ax.set_xlabel("element size at the fits (mm)")
        ax.set_ylabel("relative error")
        ax.set_title(case.name, fontsize=9)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _plot_assembly_errors(ax, case: ConvergenceCase, h: np.ndarray) -> None:
    """Per fit pressure and groove-shift vector the error of each level but the finest against
    the Richardson value (the measure of mesh_convergence_case), the target as a line."""
    n = len(case.levels) - 1
    errs = [_level_errors(case, i) for i in range(n)]
    for name in errs[0]:
        e = np.array([x[name] for x in errs])
        ok = e > 0
        if ok.any():
            ax.loglog(h[:n][ok], e[ok], "o-", lw=1, ms=3,
                      label=name.replace("fit_pressure_", "p ").replace("groove_shift_", "shift "))
    target = case.assessment.target_error
    if target is not None:
        ax.axhline(target, color="r", ls="-.", lw=1, label=f"target {100 * target:g} %")
    ax.axvline(case.used.fit_size_mm, color="0.5", lw=0.8, label="mesh used")
    ax.set_xlabel("element size at the fits (mm)")
    ax.set_ylabel("error vs Richardson")
    ax.set_title(case.name, fontsize=9)
    ax.legend(fontsize=6, ncol=2)


def run(out_dir: Path, progress=print, mesh_factor: float = 1.0, assembly=None) -> VerifyRun:
    """All verification cases into out_dir (verification.json, verification.md, PNG): the
    built-in Lamé cases and the mesh convergence (observed order, GCI) of an assembly's own
    stack: `assembly` (`verify --assembly`), else the shipped seed 000 stack. mesh_factor > 1
    coarsens the four levels of that case (smoke tests; `bearingfem verify` runs 1)."""
    from studies.model.config import load_shipped

    asm = assembly if assembly is not None else load_shipped("seed000")
    out_dir.mkdir(parents=True, exist_ok=True)
    progress("Lamé cases ...")
    cases = lame_cases()
    progress(f"Lamé cases of the {asm.name} stack's own fits and materials ...")
    cases += assembly_fit_cases(asm)
    progress(f"mesh convergence: Lamé reference and the {asm.name} stack ...")
    conv = [lame_convergence_case(progress=progress),
            mesh_convergence_case(asm, progress=progress, used=2,
                                  factors=tuple(mesh_factor * f for f in (4.0, 2.0, 1.0, 0.5)))]
    plot = plot_convergence(out_dir / "mesh_convergence.png", conv)
    progress("manufactured solutions ...")
    progress("manufactured solution of the transient conduction ...")
    result = VerifyRun(cases, conv, mms_cases(), trace(), transient_mms_cases())
    write_verification(out_dir, result.cases, plot, result.mms, result.requirements, result.convergence,
                       result.mms_transient)
    return result
