"""Lumped transient thermal network of a bearing support (seed 003): housing, outer ring, balls,
inner ring, shaft; conduction, contact and convection resistances; heat from the ball/raceway
contacts; implicit time integration and the steady state.

Units: temperatures C, heat flows W, resistances K/W, conductances W/K, capacities J/K, time s,
lengths mm (converted to m inside the resistance formulas), h in W/(m^2 K), k in W/(m K).

Model (seed 003, its eq. 42, "resistance-capacitance" network; Harris & Kotzalas Vol. 2 ch. 7 for
bearing heat transfer):

    C_i dT_i/dt = P_i(t) - sum_j (T_i - T_j)/R_ij - (T_i - T_amb)/R_i,amb

written as C dT/dt = -K T + g T_amb + P with K the weighted graph Laplacian of the internal
conductances plus diag(g), g_i = 1/R_i,amb. The chain is housing -R12- outer ring -R23- balls -R34-
inner ring -R45- shaft, with convection R_air1 (housing to ambient) and R_air5 (shaft to ambient).
Heat of a ball/raceway contact is split between the ball and that ring, equally by default
(Burton & Staph 1967, as used by seed 003). Integrated with backward Euler
((C/dt + K) T^{n+1} = C/dt T^n + g T_amb^{n+1} + P^{n+1}: unconditionally stable, first order,
conserves energy exactly in its own quadrature) or scipy's BDF.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from analytic.materials import Material

NODES = ("housing", "outer_ring", "ball", "inner_ring", "shaft")
LINKS = (("housing", "outer_ring"), ("outer_ring", "ball"), ("ball", "inner_ring"),
         ("inner_ring", "shaft"))


# --------------------------------------------------------------------------- resistances
def cylinder_conduction_resistance_K_W(d_inner_mm, d_outer_mm, length_mm, k_W_mK):
    """Radial conduction through a cylindrical wall: R = ln(d_o/d_i) / (2 pi k L)
    (Incropera & DeWitt, Fundamentals of Heat and Mass Transfer, eq. 3.33). L in mm -> m."""
    return np.log(np.asarray(d_outer_mm, float) / np.asarray(d_inner_mm, float)) / (
        2 * np.pi * np.asarray(k_W_mK, float) * np.asarray(length_mm, float) * 1e-3)


def film_resistance_K_W(h_W_m2K, area_mm2):
    """Convection or interface (contact conductance) resistance R = 1/(h A)
    (Incropera eq. 3.9 and 3.20; seed 003 eq. 41). Area in mm^2 -> m^2."""
    return 1.0 / (np.asarray(h_W_m2K, float) * np.asarray(area_mm2, float) * 1e-6)


def ball_raceway_resistance_K_W(a_mm, b_mm, k_ball_W_mK, k_ring_W_mK, n_balls):
    """Constriction resistance of the Z ball/raceway contacts in parallel: one contact of
    semi-axes a, b spreads heat into two half-spaces, R_1 = (1/k_ball + 1/k_ring) / (4 sqrt(a b))
    (Holm's isothermal-disc constriction 1/(4 k r), with the equal-area radius sqrt(a b) for the
    ellipse after Yovanovich; accurate to about 10 % for moderate ellipticity). R = R_1 / Z."""
    r_eq_m = np.sqrt(np.asarray(a_mm, float) * np.asarray(b_mm, float)) * 1e-3
    R1 = (1 / np.asarray(k_ball_W_mK, float) + 1 / np.asarray(k_ring_W_mK, float)) / (4 * r_eq_m)
    return R1 / np.asarray(n_balls, float)


# --------------------------------------------------------------------------- capacities
def ring_mass_kg(d_inner_mm, d_outer_mm, width_mm, material: Material):
    """Mass of a plain ring pi/4 (D^2 - d^2) B rho (mm^3 -> m^3)."""
    vol_m3 = np.pi / 4 * (np.asarray(d_outer_mm, float) ** 2 - np.asarray(d_inner_mm, float) ** 2) \
        * np.asarray(width_mm, float) * 1e-9
    return vol_m3 * material.density_kg_m3


def ball_set_mass_kg(ball_diameter_mm, n_balls, material: Material):
    """Mass of Z balls: Z pi/6 Dw^3 rho."""
    return np.asarray(n_balls) * np.pi / 6 * (np.asarray(ball_diameter_mm, float) * 1e-3) ** 3 \
        * material.density_kg_m3


def heat_capacity_J_K(mass_kg, material: Material):
    """Lumped heat capacity C = m c_p (J/K)."""
    return np.asarray(mass_kg, float) * material.specific_heat_J_kgK


# --------------------------------------------------------------------------- network
@dataclass(frozen=True)
class ThermalNetwork:
    """Lumped network: capacity per node (J/K), internal links (a, b) -> conductance (W/K), and
    node -> conductance to ambient (W/K). `nodes` fixes the order of every array."""
    nodes: tuple[str, ...]
    capacity_J_K: tuple[float, ...]
    conductance_W_K: dict
    ambient_conductance_W_K: dict

    def __post_init__(self):
        if len(self.capacity_J_K) != len(self.nodes) or min(self.capacity_J_K) <= 0:
            raise ValueError("one positive capacity per node is needed")
        names = set(self.nodes)
        for (a, b), G in self.conductance_W_K.items():
            if a not in names or b not in names or a == b or G < 0:
                raise ValueError(f"bad link {a}-{b}: {G}")
        for a, G in self.ambient_conductance_W_K.items():
            if a not in names or G < 0:
                raise ValueError(f"bad ambient link {a}: {G}")

    @property
    def C(self) -> np.ndarray:
        return np.asarray(self.capacity_J_K, float)

    def index(self, node: str) -> int:
        return self.nodes.index(node)

    def ambient_vector(self) -> np.ndarray:
        g = np.zeros(len(self.nodes))
        for a, G in self.ambient_conductance_W_K.items():
            g[self.index(a)] += G
        return g

    def conductance_matrix(self) -> np.ndarray:
        """K = graph Laplacian of the internal conductances + diag(ambient conductances), W/K."""
        n = len(self.nodes)
        K = np.zeros((n, n))
        for (a, b), G in self.conductance_W_K.items():
            i, j = self.index(a), self.index(b)
            K[i, i] += G
            K[j, j] += G
            K[i, j] -= G
            K[j, i] -= G
        return K + np.diag(self.ambient_vector())


def bearing_network(capacity_J_K: dict, resistance_K_W: dict) -> ThermalNetwork:
    """The 5-node network of seed 003 from capacities {node: J/K} and resistances (K/W) keyed
    'housing_outer_ring' (R12), 'outer_ring_ball' (R23), 'ball_inner_ring' (R34),
    'inner_ring_shaft' (R45), 'housing_ambient' (R_air1), 'shaft_ambient' (R_air5).
    A resistance of inf removes that path."""
    keys = {f"{a}_{b}": (a, b) for a, b in LINKS}
    missing = (set(keys) | {"housing_ambient", "shaft_ambient"}) - set(resistance_K_W)
    if missing or set(capacity_J_K) != set(NODES):
        raise ValueError(f"need capacities for {NODES} and resistances for {sorted(missing)}")
    G = {keys[k]: 1.0 / float(R) for k, R in resistance_K_W.items() if k in keys}
    Ga = {"housing": 1.0 / float(resistance_K_W["housing_ambient"]),
          "shaft": 1.0 / float(resistance_K_W["shaft_ambient"])}
    return ThermalNetwork(NODES, tuple(float(capacity_J_K[n]) for n in NODES), G, Ga)


def bearing_heat_W(Q_inner_contact_W, Q_outer_contact_W, inner_ring_share=0.5,
                   outer_ring_share=0.5, Q_housing_W=0.0, Q_shaft_W=0.0):
    """Node heat inputs (..., 5) in NODES order from the total heat of the ball/inner-raceway and
    ball/outer-raceway contacts (W): a share goes to the ring, the rest to the balls (equal split
    by default, Burton & Staph 1967 / seed 003). Optional direct heat into housing or shaft
    (e.g. a motor). Arrays broadcast (one row per time)."""
    for s in (inner_ring_share, outer_ring_share):
        if not 0.0 <= s <= 1.0:
            raise ValueError(f"ring share must lie in [0, 1], got {s}")
    Qi = np.asarray(Q_inner_contact_W, float)
    Qo = np.asarray(Q_outer_contact_W, float)
    shape = np.broadcast(Qi, Qo, np.asarray(Q_housing_W), np.asarray(Q_shaft_W)).shape
    P = np.zeros(shape + (5,))
    P[..., 0] = Q_housing_W
    P[..., 1] = outer_ring_share * Qo
    P[..., 2] = (1 - outer_ring_share) * Qo + (1 - inner_ring_share) * Qi
    P[..., 3] = inner_ring_share * Qi
    P[..., 4] = Q_shaft_W
    return P


def steady_state_C(network: ThermalNetwork, heat_W, T_ambient_C):
    """Steady node temperatures (C): K T = P + g T_amb (linear solve). Needs at least one path
    to ambient (otherwise K is singular)."""
    K = network.conductance_matrix()
    P = np.asarray(heat_W, float)
    return np.linalg.solve(K, P + network.ambient_vector() * float(T_ambient_C))


@dataclass(frozen=True)
class TransientResult:
    """Node temperatures T_C[time, node] (C); heat_W[time, node] as used; convected_W[time]
    (total to ambient at each time). energy_* in J, accumulated with the scheme's own
    quadrature (backward Euler: right end point; BDF: trapezoid)."""
    nodes: tuple[str, ...]
    time_s: np.ndarray
    T_C: np.ndarray
    heat_W: np.ndarray
    convected_W: np.ndarray
    energy_in_J: float
    energy_convected_J: float
    energy_stored_J: float

    def node(self, name: str) -> np.ndarray:
        return self.T_C[:, self.nodes.index(name)]


def simulate_transient(network: ThermalNetwork, time_s, heat_W, T_ambient_C, T_initial_C=None,
                       method: str = "backward_euler", rtol: float = 1e-8) -> TransientResult:
    """Node temperatures at the given times.

    time_s: increasing times (the first is the initial time). heat_W: node heat (n,) constant, or
    (len(time_s), n) per time (backward Euler uses the value at the END of each step; BDF
    interpolates linearly). T_ambient_C: scalar or per time. T_initial_C: scalar or (n,); default
    the first ambient temperature. method: 'backward_euler' (steps = the given times) or 'bdf'
    (scipy solve_ivp BDF with the constant Jacobian, rtol as given, output at the given times).
    """
    t = np.asarray(time_s, float)
    if t.ndim != 1 or t.size < 2 or np.any(np.diff(t) <= 0):
        raise ValueError("time_s must be a strictly increasing 1-D array of at least 2 times")
    n = len(network.nodes)
    P = np.broadcast_to(np.asarray(heat_W, float), (t.size, n)).copy()
    Ta = np.broadcast_to(np.asarray(T_ambient_C, float), t.shape).astype(float)
    T0 = np.broadcast_to(np.asarray(Ta[0] if T_initial_C is None else T_initial_C, float),
                         (n,)).astype(float)
    K = network.conductance_matrix()
    g = network.ambient_vector()
    C = network.C
    T = np.empty((t.size, n))
    T[0] = T0
    if method == "backward_euler":
        for k in range(t.size - 1):
            dt = t[k + 1] - t[k]
            A = np.diag(C / dt) + K
            T[k + 1] = np.linalg.solve(A, C / dt * T[k] + g * Ta[k + 1] + P[k + 1])
        conv = ((T - Ta[:, None]) * g).sum(axis=1)
        dt = np.diff(t)
        e_in = float((dt * P[1:].sum(axis=1)).sum())
        e_conv = float((dt * conv[1:]).sum())
    elif method == "bdf":
        def rhs(tt, y):
            Pt = np.array([np.interp(tt, t, P[:, i]) for i in range(n)])
            return (-K @ y + g * np.interp(tt, t, Ta) + Pt) / C

        jac = -K / C[:, None]
        sol = solve_ivp(rhs, (t[0], t[-1]), T0, method="BDF", t_eval=t, jac=jac, rtol=rtol,
                        atol=rtol * max(1.0, float(np.abs(T0).max())))
        if not sol.success:   # pragma: no cover
            raise RuntimeError(sol.message)
        T = sol.y.T
        conv = ((T - Ta[:, None]) * g).sum(axis=1)
        e_in = float(np.trapezoid(P.sum(axis=1), t))
        e_conv = float(np.trapezoid(conv, t))
    else:
        raise ValueError("method must be 'backward_euler' or 'bdf'")
    e_stored = float((C * (T[-1] - T[0])).sum())
    return TransientResult(network.nodes, t, T, P, conv, e_in, e_conv, e_stored)
