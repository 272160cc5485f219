"""A manufactured solution of the transient axisymmetric heat equation across a two-material fit
with a finite contact conductance: code verification of `fem.transient` in space (P2, L2 norm:
order 3) and in time (backward Euler: 1, BDF2: 2).  Used by tests/test_transient_mms.py and
listed by `bearingfem verify` (`studies.usecases.verify.transient_mms_cases`).

The field (r, z in mm, t in s), part i = 1 (shaft, TC4, r < R_F) and 2 (ring, 9Cr18):

    T_i(r, z, t) = Z(z) tau(t) (A_i + phi(r) / k_i),   phi = sin(pi r / 10),
    Z = cos(pi z / L),   tau = 2 + sin(omega t)

k_i dT_i/dr = Z tau phi' is continuous at the fit; phi'(R_I) = phi'(R_O) = 0 and Z'(0) = Z'(L) = 0
make every outer face adiabatic (the natural condition); A_2 = A_1 + phi'(R_F) / h_c gives the
contact condition -k_1 dT_1/dr = h_c (T_1 - T_2) at R_F (phi(R_F) = 0).  The source (W/mm^3) is
s_i = rho c_i dT/dt - (1/r) d/dr (r k_i dT/dr) - k_i d2T/dz2 (Incropera & DeWitt, Fundamentals
of Heat and Mass Transfer, ch. 2, the heat equation in cylindrical coordinates without the theta
terms; the method: Roache, Verification and Validation in Computational Science and
Engineering, 1998, ch. 3).  k in W/(mm K), rho c in J/(mm^3 K), h_c in W/(m^2 K).

Orders: Ciarlet, The Finite Element Method for Elliptic Problems, 1978, 3.1-3.2 (P2 in space);
backward Euler first and BDF2 second order in time (Hairer & Wanner, Solving Ordinary
Differential Equations II, 2nd ed., ch. V.1).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from skfem import asm

from analytic.materials import get_material
from fem.forms import volume_source
from fem.model import build_model
from fem.transient import (PER_M2_TO_PER_MM2, StepLoads, Stepper, ThermalParameters,
                           TransientConduction)
from meshes.section import two_cylinder_section

RI_MM, RF_MM, RO_MM, L_MM = 5.0, 10.0, 15.0, 10.0
#: fit conductance, W/(m^2 K): large enough for a visible but finite jump
H_C_W_M2K = 2.0e4
A1 = 1.0
#: rad/s: a 20 s period against diffusion times of 4-9 s over 5 mm
OMEGA_RAD_S = 2 * np.pi / 20.0
MATS = ("TC4", "9Cr18")

#: the levels `verify` runs (those of tests/test_transient_mms.py): mesh factors with BDF2 at
#: dt = 0.02 s to t = 1 s (space), time steps on the factor-1 mesh to t = 4 s (time)
SPACE_FACTORS = (1.0, 0.5, 0.25)
SPACE_DT_S, SPACE_T_END_S = 0.02, 1.0
TIME_STEPS_S = (0.8, 0.4, 0.2, 0.1, 0.05)
TIME_T_END_S = 4.0


def properties() -> list[tuple[float, float]]:
    """(k in W/(mm K), rho c in J/(mm^3 K)) of the two parts (`analytic.materials`)."""
    out = []
    for name in MATS:
        m = get_material(name)
        out.append((m.conductivity_W_mK / 1000.0, m.density_kg_m3 * m.specific_heat_J_kgK * 1e-9))
    return out


def _phi(r, d=0):
    a = np.pi / 10.0
    return [np.sin(a * r), a * np.cos(a * r), -a * a * np.sin(a * r)][d]


def _A2() -> float:
    return A1 + _phi(RF_MM, 1) / (H_C_W_M2K * PER_M2_TO_PER_MM2)


def exact(r, z, t, part: int):
    """The manufactured temperature (C) at r, z (mm), t (s) in part 0 (shaft) or 1 (ring)."""
    (k1, _), (k2, _) = properties()
    k, A = (k1, A1) if part == 0 else (k2, _A2())
    return np.cos(np.pi * z / L_MM) * (2 + np.sin(OMEGA_RAD_S * t)) * (A + _phi(r) / k)


def source(r, z, t, part: int):
    """rho c dT/dt - (1/r) d/dr(r k dT/dr) - k d2T/dz2 of `exact` (W/mm^3)."""
    (k1, rc1), (k2, rc2) = properties()
    k, rc, A = (k1, rc1, A1) if part == 0 else (k2, rc2, _A2())
    Z = np.cos(np.pi * z / L_MM)
    tau, dtau = 2 + np.sin(OMEGA_RAD_S * t), OMEGA_RAD_S * np.cos(OMEGA_RAD_S * t)
    g = A + _phi(r) / k
    return (rc * Z * dtau * g - Z * tau * (_phi(r, 2) + _phi(r, 1) / r)
            + (np.pi / L_MM) ** 2 * Z * tau * k * g)


def model(factor: float) -> TransientConduction:
    """The two-cylinder section (TC4 shaft, 9Cr18 ring) meshed at size factor `factor`."""
    sec = two_cylinder_section(RI_MM, RF_MM, RO_MM, *MATS, L_MM).scaled(factor)
    return TransientConduction(build_model(sec))


@dataclass(frozen=True)
class TransientRun:
    """One integration to t_end: the relative L2 error (2 pi r weighted) of T against `exact`,
    and T, the exact T and the weights at the quadrature points (for differences of runs)."""
    rel_error: float
    T: np.ndarray
    T_exact: np.ndarray
    weights: np.ndarray


def run(tc: TransientConduction, dt_s: float, t_end_s: float, scheme: str) -> TransientRun:
    """Integrate from the nodal interpolant of the exact field at t = 0 to t_end with `scheme`
    ("backward_euler" or "bdf2"), the manufactured source applied at every step."""
    m = tc.model
    b = m.sbasis
    part = (m.part_of != "shaft").astype(int)
    x = b.doflocs
    el_part = np.zeros(b.N, int)              # each node in its own part
    el_part[b.element_dofs[:, part == 1].ravel()] = 1
    T0 = np.where(el_part == 0, exact(x[0], x[1], 0.0, 0), exact(x[0], x[1], 0.0, 1))
    st = Stepper(tc, ThermalParameters(fit_conductance_W_m2K=(H_C_W_M2K,)), dt_s, T0, scheme)
    X = b.mapping.F(b.quadrature[0])
    pq = np.repeat(part[:, None], X.shape[2], 1)
    n = int(round(t_end_s / dt_s))
    T = T0
    for i in range(1, n + 1):
        t = i * dt_s
        s_q = np.where(pq == 0, source(X[0], X[1], t, 0), source(X[0], X[1], t, 1))
        T = st.step(StepLoads(source_W=asm(volume_source, b, s=s_q)))
    Th = np.asarray(b.interpolate(T))
    Te = np.where(pq == 0, exact(X[0], X[1], n * dt_s, 0), exact(X[0], X[1], n * dt_s, 1))
    w = b.dx * X[0]
    return TransientRun(float(np.sqrt(((Th - Te) ** 2 * w).sum() / (Te ** 2 * w).sum())), Th, Te, w)


def slope(x, e) -> float:
    """Least-squares slope of log e against log x: the observed order."""
    return float(np.polyfit(np.log(np.asarray(x, float)), np.log(np.asarray(e, float)), 1)[0])


def space_levels(factors=SPACE_FACTORS, dt_s: float = SPACE_DT_S,
                 t_end_s: float = SPACE_T_END_S) -> tuple[np.ndarray, np.ndarray]:
    """(h, relative L2 errors) per mesh factor, BDF2 at dt_s (its time error far below the
    spatial one).  h = N^-1/2 with N the DOFs, proportional to the mean element size
    (area / N)^1/2 on the fixed domain, which is all a slope needs (gmsh levels are not nested
    and the graded band along the fit does not halve with the factor)."""
    h, errs = [], []
    for f in factors:
        tc = model(f)
        h.append(tc.N ** -0.5)
        errs.append(run(tc, dt_s, t_end_s, "bdf2").rel_error)
    return np.array(h), np.array(errs)


def time_levels(scheme: str, dts=TIME_STEPS_S, t_end_s: float = TIME_T_END_S,
                factor: float = 1.0) -> tuple[np.ndarray, np.ndarray, float]:
    """(steps dt, the time error of each step but the last, the error of the smallest step
    against the exact field) on one mesh.  The time error of step dt is the distance of the
    solutions at dt and the next step to each other, |T_dt - T_dt/2| = (1 - 2^-p) |e_dt| + o: on
    one mesh the spatial error cancels from it."""
    tc = model(factor)
    runs = [run(tc, dt, t_end_s, scheme) for dt in dts]
    norm = np.sqrt((runs[0].T_exact ** 2 * runs[0].weights).sum())
    w = runs[0].weights
    diffs = [float(np.sqrt(((a.T - b.T) ** 2 * w).sum()) / norm) for a, b in zip(runs, runs[1:])]
    return np.array(dts[:-1], float), np.array(diffs), runs[-1].rel_error
