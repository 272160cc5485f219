"""An independent conduction model of the bearing stack: thermal histories made another way
than the tool's transient conduction FE.

Nothing here uses `fem/`, `fem.transient`, `fem.reduced_thermal` or
`studies.model.transient_route`: it is a radial finite-volume network of its own, with its own
constants and its own integrator, so that a diagnosis whose thermal rung is the tool's reduced
FE is tested against physics it did not write. It reads only the assembly's geometry and its
materials' conductivity, density and specific heat (`analytic.materials`).

The network (units: SI inside, m, W, J, K; temperatures in C; public names carry their unit):

- every part of the stack as `shells` concentric annular finite volumes (nodes at the mid-radius
  of each shell, capacity rho c V, conductance between neighbours the exact one of the annulus
  between the node radii, 2 pi k L / ln(r2 / r1), Incropera & DeWitt, Fundamentals of Heat and
  Mass Transfer, 6th ed., eq. 3.33): the shaft (bore to seat, over the shaft's whole length; its
  shoulder and the nut lumped into its outermost shell's capacity), the inner rings (seat to the
  inner ring's outer diameter, over both rings' width), the inner spacer (seat to its diameter),
  the outer rings (their inner diameter to the housing bore), the outer spacer (its diameter to
  the bore) and the housing (bore to outer diameter, over the shoulder and both rings and the
  spacer; its shoulder and the cover lumped into its innermost shell's capacity);
- the balls as one lumped node (2 Z balls), linked to each ring by the constriction conductance
  of its Hertz contacts (`ball_contact_conductance_W_K`);
- fit contact conductances at shaft / inner ring, shaft / inner spacer, outer ring / housing and
  outer spacer / housing (`CONTACT_W_M2K`, Incropera Tables 3.1-3.2), axial face contacts ring /
  spacer, and in air the gas layers between the rings and between the spacers (eq. 3.33 with
  the air's conductivity);
- the environment: convection to the air (forced: Churchill-Bernstein; still: Churchill-Chu;
  `film_W_m2K`) and radiation to a sink (`Environment.emissivity`); in vacuum radiation only;
- a mounting plate (`Mount`): a lumped mass with its own capacity bolted to the housing's
  shoulder end face through a joint conductance, with its own convection and radiation.

Integrated by `scipy.integrate.solve_ivp` (BDF, Jacobian of the linear part given), the ambient
linear between the rows, the heat held from each row to the next, starting in equilibrium at the
first row's ambient. The energy put in, the energy lost to the environment and the energy stored
are kept so that conservation can be checked (`NetworkHistory.energy_balance_J`).

Public API:

    Environment, Mount, ENVIRONMENTS           the cases' environments
    film_W_m2K(kind, length_m, air_speed_m_s, dT_K)
    ball_contact_conductance_W_K(asm)          all ball contacts of the pair, inner and outer
    Network, Surface, annulus_shells           the generic network (the closed-form tests use it)
    stack_network(asm, env, shells) -> StackNetwork
    conduction_temperatures(asm, time_s, T_ambient_C, env, heat_W=0, shells=4) -> NetworkHistory
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp

from analytic.materials import get_material

#: Stefan-Boltzmann constant (W/(m^2 K^4)), CODATA 2018
SIGMA_SB_W_M2K4 = 5.670374419e-8
#: 0 C in K
KELVIN_OFFSET_K = 273.15
#: standard gravity (m/s^2)
G_M_S2 = 9.80665
#: dry air at 300 K and 1 atm (Incropera & DeWitt 6th ed. Table A.4): conductivity (W/(m K)),
#: kinematic viscosity (m^2/s), thermal diffusivity (m^2/s), Prandtl number; the properties are
#: held at 300 K over the cases' -60..80 C (a documented simplification: k varies by about
#: +-20 % over that range)
AIR_K_W_MK, AIR_NU_M2_S, AIR_ALPHA_M2_S, AIR_PR = 0.0263, 15.89e-6, 22.5e-6, 0.707

#: thermal contact conductance (W/(m^2 K)) of the stack's interfaces by kind and gas: the inverse
#: of the contact resistances of Incropera & DeWitt 6th ed. Table 3.1 (metallic interfaces in
#: vacuum: stainless steel 6..25e-4 m^2 K/W at 100 kPa, 0.7..4e-4 at 10 MPa; aluminium
#: 1.5..5e-4 at 100 kPa, 0.2..0.4e-4 at 10 MPa) and Table 3.2 (interfacial fluid: an aluminium
#: interface in air 2.75e-4 m^2 K/W at 10 um roughness and 100 kPa): an interference fit (some
#: MPa of fit pressure) 1 / 4e-4 in vacuum and 1 / 1.5e-4 in air; a clearance or slip fit
#: (touching on a line under gravity, the rest a gas gap of some um) 1 / 15e-4 in vacuum and
#: 1 / 5e-4 in air; an axial face in the clamped stack (pressed by the preload path) as the
#: interference fit; a bolted joint of the mount (a few bolts over the face) 1 / 5e-4 in vacuum,
#: 1 / 2.75e-4 in air (Table 3.2's value)
CONTACT_W_M2K = {
    ("interference", "air"): 1.0 / 1.5e-4, ("interference", "vacuum"): 1.0 / 4e-4,
    ("clearance", "air"): 1.0 / 5e-4, ("clearance", "vacuum"): 1.0 / 15e-4,
    ("face", "air"): 1.0 / 1.5e-4, ("face", "vacuum"): 1.0 / 4e-4,
    ("bolted", "air"): 1.0 / 2.75e-4, ("bolted", "vacuum"): 1.0 / 5e-4,
}


# ============================================================================ films
def film_W_m2K(kind: str, length_m: float, air_speed_m_s: float = 0.0,
               dT_K: float | np.ndarray = 0.0) -> float | np.ndarray:
    """Mean convection coefficient h (W/(m^2 K)) of a face in air at 300 K (`AIR_*`).

    kind:
    - "cylinder_forced": a cylinder of diameter length_m in cross flow of air_speed_m_s,
      Churchill-Bernstein: Nu = 0.3 + 0.62 Re^(1/2) Pr^(1/3) / [1 + (0.4/Pr)^(2/3)]^(1/4)
      [1 + (Re/282000)^(5/8)]^(4/5) (Incropera & DeWitt 6th ed. eq. 7.54, Re Pr > 0.2);
    - "cylinder_natural": a horizontal cylinder of diameter length_m at a difference dT_K from
      the air, Churchill-Chu: Nu = {0.60 + 0.387 Ra^(1/6) / [1 + (0.559/Pr)^(9/16)]^(8/27)}^2
      (eq. 9.34, Ra < 1e12), Ra = g beta |dT| D^3 / (nu alpha), beta = 1 / 300 K (ideal gas);
    - "plate_forced": a flat plate of length length_m along a flow of air_speed_m_s, laminar
      mean Nu = 0.664 Re^(1/2) Pr^(1/3) (eq. 7.30, Re < 5e5);
    - "plate_natural": a vertical plate of height length_m, Churchill-Chu: Nu = {0.825 + 0.387
      Ra^(1/6) / [1 + (0.492/Pr)^(9/16)]^(8/27)}^2 (eq. 9.26).
    h = Nu k / length_m. Natural convection depends on dT_K (an array is evaluated element-wise)."""
    if length_m <= 0.0:
        raise ValueError(f"film_W_m2K: length_m must be > 0, got {length_m}")
    k, nu, alpha, pr = AIR_K_W_MK, AIR_NU_M2_S, AIR_ALPHA_M2_S, AIR_PR
    if kind in ("cylinder_forced", "plate_forced"):
        if air_speed_m_s <= 0.0:
            raise ValueError(f"film_W_m2K: {kind} needs air_speed_m_s > 0, got {air_speed_m_s}")
        re = air_speed_m_s * length_m / nu
        if kind == "plate_forced":
            nusselt = 0.664 * math.sqrt(re) * pr ** (1.0 / 3.0)
        else:
            nusselt = 0.3 + (0.62 * math.sqrt(re) * pr ** (1.0 / 3.0)
                             / (1.0 + (0.4 / pr) ** (2.0 / 3.0)) ** 0.25
                             * (1.0 + (re / 282000.0) ** 0.625) ** 0.8)
        return nusselt * k / length_m
    if kind in ("cylinder_natural", "plate_natural"):
        ra = G_M_S2 / 300.0 * np.abs(dT_K) * length_m ** 3 / (nu * alpha)
        a, c = (0.60, 0.559) if kind == "cylinder_natural" else (0.825, 0.492)
        nusselt = (a + 0.387 * ra ** (1.0 / 6.0) / (1.0 + (c / pr) ** (9.0 / 16.0)) ** (8.0 / 27.0)) ** 2
        return nusselt * k / length_m
    raise ValueError(f"film_W_m2K: unknown kind {kind!r}")


# ============================================================================ environments
@dataclass(frozen=True)
class Mount:
    """What the housing is bolted to: a plate of `material`, length x width x thickness (mm),
    bolted to the housing's shoulder end face (contact `CONTACT_W_M2K[("bolted", gas)]` over that
    face's annulus), its two large faces exchanging with the environment like the housing
    (a plate film, its own emissivity)."""
    material: str = "6061"
    length_mm: float = 150.0
    width_mm: float = 150.0
    thickness_mm: float = 10.0
    emissivity: float = 0.1          # bare machined aluminium: 0.05..0.1 (Incropera Table A.11)

    def capacity_J_K(self) -> float:
        m = get_material(self.material)
        return (m.density_kg_m3 * m.specific_heat_J_kgK
                * self.length_mm * self.width_mm * self.thickness_mm * 1e-9)

    def area_m2(self) -> float:
        """Both large faces (m^2)."""
        return 2.0 * self.length_mm * self.width_mm * 1e-6


@dataclass(frozen=True)
class Environment:
    """The stack's surroundings. gas: "air" or "vacuum"; air_speed_m_s: 0 = still air (natural
    convection), > 0 = forced across the housing; emissivity of the stack's outer faces
    (radiation to a sink at the ambient: the chamber's walls or shroud follow its set point);
    mount: the plate the housing is bolted to (None: the stack hangs free)."""
    name: str
    gas: str = "air"
    air_speed_m_s: float = 0.0
    emissivity: float = 0.0
    mount: Mount | None = None

    def __post_init__(self):
        if self.gas not in ("air", "vacuum"):
            raise ValueError(f"Environment {self.name}: gas must be air or vacuum, got {self.gas!r}")
        if self.gas == "vacuum" and self.air_speed_m_s:
            raise ValueError(f"Environment {self.name}: no air speed in vacuum")


#: the thermal-history cases' environments: a climate chamber with its fan (2 m/s across the
#: housing), still air, a thermal-vacuum chamber (black-anodised housing, emissivity 0.8,
#: Incropera Table A.11: anodised aluminium 0.82), and the chamber with the housing bolted to an
#: aluminium plate 150 x 150 x 10 mm (about 0.6 kg, 550 J/K)
ENVIRONMENTS = {
    "forced_air": Environment("forced_air", "air", 2.0, 0.1),
    "still_air": Environment("still_air", "air", 0.0, 0.1),
    "vacuum": Environment("vacuum", "vacuum", 0.0, 0.8),
    "mount_forced_air": Environment("mount_forced_air", "air", 2.0, 0.1, Mount()),
}


# ============================================================================ generic network
@dataclass(frozen=True)
class Surface:
    """A face of node `node` of area_m2 exchanging with the environment: convection of film
    (W/(m^2 K): a number, or a function of T_face - T_ambient in K) and radiation of emissivity
    to the sink (the ambient), h_r = eps sigma (T^2 + T_amb^2)(T + T_amb) in K (Incropera &
    DeWitt eq. 1.9: radiation as a coefficient on T - T_amb), through the wall conductance
    wall_W_K from the node to the face (the half shell; infinite: the node is the face).
    `Network.surface_conductance_W_K` evaluates it."""
    node: int
    area_m2: float
    film: float | Callable[[np.ndarray], np.ndarray] = 0.0
    emissivity: float = 0.0
    wall_W_K: float = math.inf


@dataclass
class Network:
    """A thermal network: capacity_J_K per node, the symmetric conductance matrix between nodes
    conductance_W_K (n x n, zero diagonal), surfaces to the environment, and each node's share of
    the heat input (heat_share, summing to 1 or all zero)."""
    capacity_J_K: np.ndarray
    conductance_W_K: np.ndarray
    surfaces: list[Surface] = field(default_factory=list)
    heat_share: np.ndarray | None = None

    @property
    def n(self) -> int:
        return int(self.capacity_J_K.size)

    def link(self, i: int, j: int, G_W_K: float) -> None:
        """Add a conductance between nodes i and j (parallel to any already there)."""
        if i == j or G_W_K < 0:
            raise ValueError(f"Network.link: bad link {i}-{j} of {G_W_K} W/K")
        self.conductance_W_K[i, j] += G_W_K
        self.conductance_W_K[j, i] += G_W_K

    def laplacian_W_K(self) -> np.ndarray:
        """L = diag(row sums of G) - G: the internal heat flow out of every node is L T."""
        G = self.conductance_W_K
        return np.diag(G.sum(axis=1)) - G

    def surface_conductance_W_K(self, T_C: np.ndarray, T_amb_C: float) -> np.ndarray:
        """Every node's conductance to the environment (W/K), the sum over its surfaces of the
        wall in series with A (h + h_r) (`Surface`), the film and h_r evaluated at the face's
        temperature: first at the node's, then once more at the face temperature that gives
        (T_face - T_amb = (T_node - T_amb) G / (A (h + h_r)), G the series conductance; the
        residual error is second order in the wall's drop, which is itself first order in the
        shell width). Vectorised over the surfaces: the integrator calls it at every stage."""
        node, area, eps, wall, const, films = self._surface_arrays()
        dT_node = np.asarray(T_C, float)[node] - T_amb_C
        Ta = T_amb_C + KELVIN_OFFSET_K

        def face_g(dT):
            h = const.copy()
            for k, f in films:
                h[k] = f(dT[k])
            Tk = dT + Ta
            h = h + eps * SIGMA_SB_W_M2K4 * (Tk * Tk + Ta * Ta) * (Tk + Ta)
            return h * area

        g_face = face_g(dT_node)
        with np.errstate(divide="ignore", invalid="ignore"):
            g = np.where(g_face > 0.0, 1.0 / (1.0 / np.maximum(g_face, 1e-300) + 1.0 / wall), 0.0)
            g_face = face_g(dT_node * np.where(g_face > 0.0, g / np.maximum(g_face, 1e-300), 1.0))
            g = np.where(g_face > 0.0, 1.0 / (1.0 / np.maximum(g_face, 1e-300) + 1.0 / wall), 0.0)
        return np.bincount(node, g, minlength=self.n)

    def _surface_arrays(self):
        key = len(self.surfaces)
        if getattr(self, "_arrays", (None,))[0] != key:
            node = np.array([s.node for s in self.surfaces], int)
            area = np.array([s.area_m2 for s in self.surfaces], float)
            eps = np.array([s.emissivity for s in self.surfaces], float)
            wall = np.array([s.wall_W_K for s in self.surfaces], float)
            const = np.array([0.0 if callable(s.film) else s.film for s in self.surfaces], float)
            films = [(k, s.film) for k, s in enumerate(self.surfaces) if callable(s.film)]
            self._arrays = (key, (node, area, eps, wall, const, films))
        return self._arrays[1]

    def losses_W(self, T_C: np.ndarray, T_amb_C: float) -> np.ndarray:
        """Heat each node loses to the environment (W) at node temperatures T_C:
        `surface_conductance_W_K` x (T - T_amb) (convection, Incropera eq. 1.3a, and radiation,
        eq. 1.7, exact in T^4 when the wall is infinite)."""
        return self.surface_conductance_W_K(T_C, T_amb_C) * (np.asarray(T_C, float) - T_amb_C)

    def integrate(self, time_s: np.ndarray, T_ambient_C: np.ndarray, heat_W=0.0,
                  T0_C: np.ndarray | float | None = None, rtol: float = 1e-7,
                  atol_K: float = 1e-5) -> tuple[np.ndarray, np.ndarray]:
        """Node temperatures (rows x nodes, C) and the energy ledger (rows x 3: put in, lost to
        the environment, stored; J) at time_s, for the ambient linear between the rows and the
        heat (a number or one per row, held from each row to the next; or a `BearingHeat`,
        the heat at the bearing's own temperature at every instant, each row's conditions
        held to the next). Starts at T0_C (default: uniform at the first row's ambient).
        C dT/dt = -L T - losses(T) + share Q(t, T), by solve_ivp BDF (Hairer & Wanner, Solving
        ODEs II, ch. IV.1: stiff; Shampine & Reichelt 1997) with steps no longer than the
        shortest row interval."""
        t = np.asarray(time_s, float)
        u = np.asarray(T_ambient_C, float)
        if t.ndim != 1 or t.size < 2 or np.any(np.diff(t) <= 0):
            raise ValueError("Network.integrate: time_s must hold 2 or more increasing values")
        law = heat_W if isinstance(heat_W, BearingHeat) else None
        q = np.zeros(t.shape) if law else np.broadcast_to(np.asarray(heat_W, float), t.shape)
        share = self.heat_share if self.heat_share is not None else np.zeros(self.n)
        C = np.asarray(self.capacity_J_K, float)
        L = self.laplacian_W_K()
        n = self.n
        T0 = np.full(n, u[0]) if T0_C is None else np.broadcast_to(np.asarray(T0_C, float), (n,)).copy()

        def row_at(tt):
            return min(max(int(np.searchsorted(t, tt, side="right")) - 1, 0), t.size - 1)

        def heat_at(tt, T):
            """(Q (W), dQ/dT (W/K per node)) at time tt and node temperatures T."""
            k = row_at(tt)
            if law is None:
                return q[k], None
            Q, dQ = law.at(k, float(law.oil_weights @ T))
            return Q, dQ * law.oil_weights

        def rhs(tt, y):
            T = y[:n]
            amb = float(np.interp(tt, t, u))
            Q, _ = heat_at(tt, T)
            loss = self.losses_W(T, amb)
            dT = (-L @ T - loss + share * Q) / C
            return np.concatenate([dT, [Q, loss.sum()]])

        def jac(tt, y):
            T = y[:n]
            amb = float(np.interp(tt, t, u))
            J = np.zeros((n + 2, n + 2))
            dl = self.surface_conductance_W_K(T, amb)       # conductances held: an
            #                                                 approximate Jacobian steers Newton
            J[:n, :n] = -(L + np.diag(dl)) / C[:, None]
            J[n + 1, :n] = dl
            _, dQ = heat_at(tt, T)
            if dQ is not None:                               # the heat's own slope
                J[:n, :n] += np.outer(share, dQ) / C[:, None]
                J[n, :n] = dQ
            return J

        sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([T0, [0.0, 0.0]]), method="BDF",
                        t_eval=t, jac=jac, rtol=rtol, atol=atol_K,
                        max_step=float(np.min(np.diff(t))))
        if not sol.success:
            raise RuntimeError(f"Network.integrate: solve_ivp failed: {sol.message}")
        T = sol.y[:n].T
        stored = (T - T0) @ C
        return T, np.column_stack([sol.y[n], sol.y[n + 1], stored])



@dataclass(frozen=True)
class BearingHeat:
    """The bearing's friction heat at its own temperature (`Network.integrate`): T_C (n_T,) an
    increasing grid of the bearing's temperature (C), ln_heat (n_sets, n_T) ln of the heat (W)
    of each set of conditions at the grid's temperatures (interpolated linearly in between,
    held beyond), row_set (n_rows,) each row's set, oil_weights (n_nodes,) the bearing's
    temperature as a weighted mean of the nodes (the rings' and balls' volume means, summing
    to 1). P = M omega at the bearing's temperature: the heat the rows' torque dissipates
    (Harris & Kotzalas vol. 2 ch. 7), so the energy put in is the torque's own."""
    T_C: np.ndarray
    ln_heat: np.ndarray
    row_set: np.ndarray
    oil_weights: np.ndarray

    def at(self, k: int, T_C: float) -> tuple[float, float]:
        """(heat (W), its slope dQ/dT (W/K)) of row k's conditions with the bearing at T_C."""
        y = self.ln_heat[self.row_set[k]]
        j = int(np.clip(np.searchsorted(self.T_C, T_C) - 1, 0, self.T_C.size - 2))
        slope = (y[j + 1] - y[j]) / (self.T_C[j + 1] - self.T_C[j])
        inside = self.T_C[0] <= T_C <= self.T_C[-1]
        Q = float(np.exp(np.interp(T_C, self.T_C, y)))
        return Q, (Q * slope if inside else 0.0)


def _film(gas: str, air_speed_m_s: float, shape: str, length_m: float):
    """The film of a face of `shape` ("cylinder": diameter, "plate": length `length_m`, m) for
    `film_W_m2K`: forced convection (a number, W/(m^2 K)) where the air moves, natural convection
    (a function of the face's temperature difference, K) in still air, 0 in vacuum."""
    if gas != "air":
        return 0.0
    if air_speed_m_s > 0:
        return film_W_m2K(f"{shape}_forced", length_m, air_speed_m_s)
    return lambda dT: film_W_m2K(f"{shape}_natural", length_m, 0.0, dT)


def annulus_shells(r_in_m: float, r_out_m: float, length_m: float, conductivity_W_mK: float,
                   rho_c_J_m3K: float, shells: int):
    """Finite volumes of an annulus r_in..r_out (m) of length length_m: (node radii m,
    capacities J/K, conductances between neighbours W/K, conductance from the first node to the
    inner face and from the last node to the outer face W/K). Equal radial widths, nodes at the
    mid-radius of each shell; every conductance the exact one of the annulus between its two
    radii, 2 pi k L / ln(r2 / r1) (Incropera & DeWitt 6th ed. eq. 3.33)."""
    if not 0.0 <= r_in_m < r_out_m or shells < 1:
        raise ValueError(f"annulus_shells: bad annulus {r_in_m}..{r_out_m} m, {shells} shells")
    edges = np.linspace(r_in_m, r_out_m, shells + 1)
    rc = 0.5 * (edges[:-1] + edges[1:])
    cap = rho_c_J_m3K * math.pi * (edges[1:] ** 2 - edges[:-1] ** 2) * length_m
    g = 2.0 * math.pi * conductivity_W_mK * length_m
    between = g / np.log(rc[1:] / rc[:-1])
    to_inner = g / math.log(rc[0] / r_in_m) if r_in_m > 0 else math.inf
    to_outer = g / math.log(r_out_m / rc[-1])
    return rc, cap, between, to_inner, to_outer


def condensed(net: Network, n_keep: int) -> Network:
    """The network on its first n_keep nodes with the others (capacity 0: faces) eliminated by
    static condensation: L_c = L_kk - L_kf L_ff^-1 L_fk, the Schur complement of the Laplacian
    (the star-mesh transform of network theory, Kron reduction: Doerfler & Bullo, IEEE Trans.
    Circuits Syst. I 60 (2013) 150-163), again symmetric with zero row sums, so the steady and
    transient answers on the kept nodes are unchanged and heat is conserved."""
    if np.any(net.capacity_J_K[n_keep:] != 0.0):
        raise ValueError("condensed: only nodes without capacity can be eliminated")
    L = net.laplacian_W_K()
    k, f = slice(0, n_keep), slice(n_keep, net.n)
    Lc = L[k, k] - L[k, f] @ np.linalg.solve(L[f, f], L[f, k])
    G = -Lc
    np.fill_diagonal(G, 0.0)
    G = 0.5 * (G + G.T)
    return Network(net.capacity_J_K[:n_keep].copy(), np.maximum(G, 0.0), list(net.surfaces),
                   None if net.heat_share is None else net.heat_share[:n_keep].copy())


def series(*G_W_K: float) -> float:
    """Conductances in series: 1 / sum(1 / G) (W/K; an infinite one adds nothing)."""
    return 1.0 / sum(1.0 / g for g in G_W_K if math.isfinite(g))


# ============================================================================ the stack
def ball_contact_conductance_W_K(asm) -> tuple[float, float]:
    """(inner, outer) conductance (W/K) of all the pair's ball-raceway contacts: per contact the
    constriction resistance of a circular contact of radius c between two half-spaces,
    R = 1/(4 c k_ball) + 1/(4 c k_ring) (Carslaw & Jaeger, Conduction of Heat in Solids, 2nd ed.,
    sec. 8.2; Yovanovich's constriction resistance of an isothermal disc), c the Hertz contact's
    equivalent radius sqrt(a b) = (3 Q R_e / (4 E*))^(1/3) (Johnson, Contact Mechanics, eq. 4.33
    with F1(e) = 1), R_e = sqrt(Rx Ry), 1/Rx = 2/D +- 2/d_race (the race diameter at the contact
    d_m -+ D cos alpha), 1/Ry = 2/D - 1/(f D); Q = the assembled preload over Z sin alpha (the
    free contact angle), 2 Z contacts on each ring (two bearings)."""
    b = asm.bearing
    ball = get_material(b.ball_material, asm.materials)
    ring = get_material(b.ring_material, asm.materials)
    D = b.ball_diameter_mm * 1e-3
    dm = b.pitch_diameter_mm * 1e-3
    alpha = math.radians(b.contact_angle_free_deg)
    Q = max(asm.preload.assembled_N, 1.0) / (b.ball_count * math.sin(alpha))
    E_star = 1.0 / ((1 - ball.nu ** 2) / (ball.E_MPa * 1e6) + (1 - ring.nu ** 2) / (ring.E_MPa * 1e6))
    out = []
    for sign, f in ((+1.0, b.inner_groove_ratio), (-1.0, b.outer_groove_ratio)):
        d_race = dm - sign * D * math.cos(alpha)
        inv_rx = 2.0 / D + sign * 2.0 / d_race
        inv_ry = 2.0 / D - 1.0 / (f * D)
        Re = 1.0 / math.sqrt(inv_rx * inv_ry)
        c = (3.0 * Q * Re / (4.0 * E_star)) ** (1.0 / 3.0)
        R = 1.0 / (4.0 * c * ball.conductivity_W_mK) + 1.0 / (4.0 * c * ring.conductivity_W_mK)
        out.append(2 * b.ball_count / R)
    return out[0], out[1]


#: the parts of the network and the pipeline column each feeds (`T_spacer_C` is both spacers:
#: their volume mean, `studies.model.inputs.PhysicsInputs`)
PART_COLUMN = {"shaft": "T_shaft_C", "inner_ring": "T_inner_ring_C", "ball": "T_ball_C",
               "outer_ring": "T_outer_ring_C", "housing": "T_housing_C",
               "inner_spacer": "T_spacer_C", "outer_spacer": "T_spacer_C"}


@dataclass
class StackNetwork:
    """The network of a stack (`stack_network`): nodes of each part (`parts`: part -> node
    indices), their volumes (m^3) for the part means, and the mount's node (None without)."""
    network: Network
    parts: dict[str, np.ndarray]
    volume_m3: np.ndarray
    mount_node: int | None
    env: Environment

    def oil_weights(self) -> np.ndarray:
        """(n_nodes,) weights of the bearing's temperature: the mean of the inner rings', the
        balls' and the outer rings' volume means (as the tool takes its oil temperature)."""
        w = np.zeros(self.volume_m3.size)
        for part in ("inner_ring", "ball", "outer_ring"):
            idx = self.parts[part]
            w[idx] += self.volume_m3[idx] / self.volume_m3[idx].sum() / 3.0
        return w

    def part_means_C(self, T_C: np.ndarray) -> dict[str, np.ndarray]:
        """Volume means (rows) of the pipeline's part columns (`PART_COLUMN`) of node
        temperatures T_C (rows x nodes)."""
        out: dict[str, list] = {}
        for part, idx in self.parts.items():
            out.setdefault(PART_COLUMN[part], []).append(idx)
        means = {}
        for col, groups in out.items():
            idx = np.concatenate(groups)
            w = self.volume_m3[idx]
            means[col] = T_C[:, idx] @ w / w.sum()
        return means


def stack_network(asm, env: Environment, shells: int = 4) -> StackNetwork:
    """The conduction network of an assembly's stack in `env` (module docstring). Stacks with a
    sleeve or cartridge are not modelled (ValueError)."""
    if asm.layers():
        raise ValueError(f"{asm.name}: conduction_network models no sleeve or cartridge")
    if shells < 1:
        raise ValueError(f"stack_network: shells must be >= 1, got {shells}")
    gas = env.gas
    mm = 1e-3
    s, h, b = asm.shaft, asm.housing, asm.bearing
    two_B = 2.0 * b.width_mm * mm
    r_bore, r_seat = s.bore_diameter_mm / 2 * mm, s.seat_diameter_mm / 2 * mm
    r_iro, r_ori = b.inner_ring_outer_diameter_mm / 2 * mm, b.outer_ring_inner_diameter_mm / 2 * mm
    r_hb, r_ho = h.bore_diameter_mm / 2 * mm, h.outer_diameter_mm / 2 * mm
    r_isp, r_osp = asm.inner_spacer.diameter_mm / 2 * mm, asm.outer_spacer.diameter_mm / 2 * mm
    L_isp, L_osp = asm.inner_spacer.length_mm * mm, asm.outer_spacer.length_mm * mm
    L_shaft = (s.shoulder_width_mm + 2 * b.width_mm + asm.inner_spacer.length_mm
               + asm.nut.width_mm + s.extension_mm) * mm
    L_house = (h.shoulder_width_mm + 2 * b.width_mm + asm.outer_spacer.length_mm) * mm

    def mat(name):
        return get_material(name, asm.materials)

    caps, vols, parts = [], [], {}
    blocks = {}

    def add_annulus(part, r0, r1, length, material):
        m = mat(material)
        rc, cap, between, g_in, g_out = annulus_shells(
            r0, r1, length, m.conductivity_W_mK, m.density_kg_m3 * m.specific_heat_J_kgK, shells)
        first = len(caps)
        caps.extend(cap)
        vols.extend(cap / (m.density_kg_m3 * m.specific_heat_J_kgK))
        parts[part] = np.arange(first, first + shells)
        blocks[part] = (r0, r1, length, m, between, g_in, g_out)

    add_annulus("shaft", r_bore, r_seat, L_shaft, s.material)
    add_annulus("inner_ring", r_seat, r_iro, two_B, b.ring_material)
    add_annulus("inner_spacer", r_seat, r_isp, L_isp, asm.inner_spacer.material)
    add_annulus("outer_ring", r_ori, r_hb, two_B, b.ring_material)
    add_annulus("outer_spacer", r_osp, r_hb, L_osp, asm.outer_spacer.material)
    add_annulus("housing", r_hb, r_ho, L_house, h.material)
    ball = get_material(b.ball_material, asm.materials)
    v_ball = 2 * b.ball_count * math.pi / 6.0 * (b.ball_diameter_mm * mm) ** 3
    parts["ball"] = np.array([len(caps)])
    caps.append(ball.density_kg_m3 * ball.specific_heat_J_kgK * v_ball)
    vols.append(v_ball)
    mount_node = None
    if env.mount is not None:
        mount_node = len(caps)
        caps.append(env.mount.capacity_J_K())
        vols.append(0.0)            # not a stack part
    caps = np.array(caps)
    # the shaft's shoulder and the nut, the housing's shoulder and the cover: their capacity
    # only (short, stubby, well connected), spread over the part's shells in proportion to their
    # own (a capacity held at one shell would move with the shell width: a first-order error)
    sh, nut = mat(s.material), mat(asm.nut.material)
    hm, cov = mat(h.material), mat(asm.cover.material)
    extra = {
        "shaft": (sh.density_kg_m3 * sh.specific_heat_J_kgK * math.pi * (
            (s.shoulder_diameter_mm / 2 * mm) ** 2 - r_seat ** 2) * s.shoulder_width_mm * mm
            + nut.density_kg_m3 * nut.specific_heat_J_kgK * math.pi * (
            (asm.nut.diameter_mm / 2 * mm) ** 2 - r_seat ** 2) * asm.nut.width_mm * mm),
        "housing": (hm.density_kg_m3 * hm.specific_heat_J_kgK * math.pi * (
            r_hb ** 2 - (h.shoulder_diameter_mm / 2 * mm) ** 2) * h.shoulder_width_mm * mm
            + cov.density_kg_m3 * cov.specific_heat_J_kgK * math.pi * (
            r_ho ** 2 - (asm.cover.diameter_mm / 2 * mm) ** 2) * asm.cover.width_mm * mm)}
    for part, c_J_K in extra.items():
        idx = parts[part]
        caps[idx] += c_J_K * caps[idx] / caps[idx].sum()
    # the faces several links share (the shaft's seat, the housing's bore, the raceway faces of
    # the rings) are nodes without capacity, condensed out at the end (`condensed`): a half
    # shell shared by two links is then exact (two separate series links, or one scaled by a
    # length share, would each carry a first-order error in the shell width)
    n_real = caps.size
    F_seat, F_bore, F_iro, F_ori = range(n_real, n_real + 4)
    net = Network(np.concatenate([caps, np.zeros(4)]), np.zeros((n_real + 4, n_real + 4)))
    for part, (r0, r1, length, m, between, g_in, g_out) in blocks.items():
        idx = parts[part]
        for k, g in enumerate(between):
            net.link(idx[k], idx[k + 1], g)

    def outer_of(part):
        return parts[part][-1], blocks[part][6]

    def inner_of(part):
        return parts[part][0], blocks[part][5]

    fit_in = "interference" if asm.fits.inner_interference_um > 0 else "clearance"
    fit_out = "interference" if asm.fits.outer_interference_um > 0 else "clearance"
    # radial fits: the shaft's seat carries the inner rings and the inner spacer, the housing's
    # bore the outer rings and the outer spacer (the shaft and the housing axially uniform)
    a, ga = outer_of("shaft")
    net.link(a, F_seat, ga)
    for part, kind, length in (("inner_ring", fit_in, two_B), ("inner_spacer", "clearance", L_isp)):
        c, gc = inner_of(part)
        net.link(F_seat, c, series(CONTACT_W_M2K[(kind, gas)] * 2 * math.pi * r_seat * length, gc))
    c, gc = inner_of("housing")
    net.link(c, F_bore, gc)
    for part, kind, length in (("outer_ring", fit_out, two_B), ("outer_spacer", "clearance", L_osp)):
        a, ga = outer_of(part)
        net.link(a, F_bore, series(ga, CONTACT_W_M2K[(kind, gas)] * 2 * math.pi * r_hb * length))
    # balls: Hertz constriction to each ring's raceway face
    g_bi, g_bo = ball_contact_conductance_W_K(asm)
    net.link(outer_of("inner_ring")[0], F_iro, outer_of("inner_ring")[1])
    net.link(inner_of("outer_ring")[0], F_ori, inner_of("outer_ring")[1])
    net.link(parts["ball"][0], F_iro, g_bi)
    net.link(parts["ball"][0], F_ori, g_bo)
    # axial faces ring / spacer (two on each side), shell by shell where the annuli overlap:
    # the face contact in series with the half lengths' axial conduction k A / (L / 2)
    for ring, spacer in (("inner_ring", "inner_spacer"), ("outer_ring", "outer_spacer")):
        rr0, rr1, Lr, mr, *_ = blocks[ring]
        sr0, sr1, Ls, ms, *_ = blocks[spacer]
        re = np.linspace(rr0, rr1, shells + 1)
        se = np.linspace(sr0, sr1, shells + 1)
        for i in range(shells):
            for j in range(shells):
                lo, hi = max(re[i], se[j]), min(re[i + 1], se[j + 1])
                if hi <= lo:
                    continue
                A = 2.0 * math.pi * (hi ** 2 - lo ** 2)      # two faces (A and B), pi (hi^2 - lo^2) each
                g = series(mr.conductivity_W_mK * A / (Lr / 4),  # each ring's half width B / 2
                           CONTACT_W_M2K[("face", gas)] * A,
                           ms.conductivity_W_mK * A / (Ls / 2))
                net.link(parts[ring][i], parts[spacer][j], g)
    # gas layers in air: between the rings (the bearing's annular space) and between the spacers
    if gas == "air":
        net.link(F_iro, F_ori, 2.0 * math.pi * AIR_K_W_MK * two_B / math.log(r_ori / r_iro))
        if r_osp > r_isp:
            (a, ga), (c, gc) = outer_of("inner_spacer"), inner_of("outer_spacer")
            g_air = 2.0 * math.pi * AIR_K_W_MK * min(L_isp, L_osp) / math.log(r_osp / r_isp)
            net.link(a, c, series(ga, g_air, gc))
    # the environment
    eps = env.emissivity
    D_ho = 2 * r_ho
    h_house = _film(gas, env.air_speed_m_s, "cylinder", D_ho)
    h_inside = ((lambda dT, _D=2 * max(r_bore, 1e-3): film_W_m2K("cylinder_natural", _D, 0.0, dT))
                if gas == "air" else 0.0)
    surfaces = []
    hi_, g_out_house = outer_of("housing")
    # the housing's outer cylinder through its half shell, its two end faces by shell area (the
    # shoulder end goes to the mount when there is one)
    surfaces.append(Surface(hi_, 2 * math.pi * r_ho * L_house, h_house, eps, g_out_house))
    house_edges = np.linspace(r_hb, r_ho, shells + 1)
    ends = 1 if env.mount is not None else 2
    for k, node in enumerate(parts["housing"]):
        A = math.pi * (house_edges[k + 1] ** 2 - house_edges[k] ** 2)
        surfaces.append(Surface(int(node), ends * A, h_house, eps))
    # the shaft: its bore (still air inside; radiation to the bore's far ends neglected: a
    # cavity) and its two end annuli
    shaft_edges = np.linspace(r_bore, r_seat, shells + 1)
    if r_bore > 0:
        surfaces.append(Surface(int(parts["shaft"][0]), 2 * math.pi * r_bore * L_shaft, h_inside,
                                0.0, blocks["shaft"][5]))
    for k, node in enumerate(parts["shaft"]):
        A = math.pi * (shaft_edges[k + 1] ** 2 - shaft_edges[k] ** 2)
        surfaces.append(Surface(int(node), 2 * A, h_house, eps))
    if env.mount is not None:
        mt = env.mount
        for k, node in enumerate(parts["housing"]):
            A = math.pi * (house_edges[k + 1] ** 2 - house_edges[k] ** 2)
            g_axial = hm.conductivity_W_mK * A / (L_house / 2)
            net.link(int(node), mount_node, series(g_axial, CONTACT_W_M2K[("bolted", gas)] * A))
        Lp = mt.length_mm * mm
        h_plate = _film(gas, env.air_speed_m_s, "plate", Lp)
        surfaces.append(Surface(mount_node, mt.area_m2(), h_plate, mt.emissivity))
    net = condensed(net, n_real)
    net.surfaces = surfaces
    share = np.zeros(caps.size)
    # the friction heat: half into each ring's raceway shell (Harris & Kotzalas, Rolling Bearing
    # Analysis 5th ed. vol. 2 ch. 7: the heat generated at the contacts divides between the
    # raceways; the balls, in rolling, pass it on)
    share[parts["inner_ring"][-1]] = 0.5
    share[parts["outer_ring"][0]] = 0.5
    net.heat_share = share
    return StackNetwork(net, parts, np.array(vols), mount_node, env)


@dataclass(frozen=True)
class NetworkHistory:
    """A thermal history of the conduction network at the rows: the pipeline's part columns
    (`T_shaft_C`, `T_inner_ring_C`, `T_ball_C`, `T_outer_ring_C`, `T_housing_C`, `T_spacer_C`;
    `columns`), the mount's temperature (C, None without a mount), the energy ledger (J: put in,
    lost to the environment, stored, per row) and the node temperatures (rows x nodes)."""
    time_s: np.ndarray
    columns: dict[str, np.ndarray]
    T_mount_C: np.ndarray | None
    energy_in_J: np.ndarray
    energy_lost_J: np.ndarray
    energy_stored_J: np.ndarray
    nodes_C: np.ndarray

    def energy_balance_J(self) -> np.ndarray:
        """Put in - lost - stored per row (J): zero up to the integrator's tolerance."""
        return self.energy_in_J - self.energy_lost_J - self.energy_stored_J


def conduction_temperatures(asm, time_s, T_ambient_C, env: Environment | str, heat_W=0.0,
                            shells: int = 4, rtol: float = 1e-7) -> NetworkHistory:
    """The part temperatures of the assembly's stack in `env` (an `Environment` or a key of
    ENVIRONMENTS) following T_ambient_C at time_s, with the bearing heat heat_W (W: a number or
    one per row, held to the next row; or a `BearingHeat`, at the bearing's own temperature,
    its weights set here) fed half to each ring's raceway; starts in equilibrium at the first
    row's ambient (`stack_network`, `Network.integrate`)."""
    if isinstance(env, str):
        if env not in ENVIRONMENTS:
            raise ValueError(f"unknown environment {env!r} (known: {', '.join(ENVIRONMENTS)})")
        env = ENVIRONMENTS[env]
    sn = stack_network(asm, env, shells)
    if isinstance(heat_W, BearingHeat):
        heat_W = replace(heat_W, oil_weights=sn.oil_weights())
    T, ledger = sn.network.integrate(time_s, T_ambient_C, heat_W, rtol=rtol)
    cols = sn.part_means_C(T)
    order = ("T_shaft_C", "T_inner_ring_C", "T_ball_C", "T_outer_ring_C", "T_housing_C", "T_spacer_C")
    return NetworkHistory(np.asarray(time_s, float), {c: cols[c] for c in order},
                          T[:, sn.mount_node] if sn.mount_node is not None else None,
                          ledger[:, 0], ledger[:, 1], ledger[:, 2], T)
