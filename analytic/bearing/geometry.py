"""Bearing geometry: the free internal geometry of one bearing, its thermally grown state, and the
pair conventions (arrangement signs, per-bearing array shapes). Units: mm, C; angles in degrees
at the interface. Notation: Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 1 ch. 2."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic import hertz
from analytic.catalogue import BearingSpec, get_entry  # BearingSpec: re-exported, its old home
from analytic.materials import Material, get_material


@dataclass(frozen=True)
class BearingGeometry:
    """Internal geometry of one angular-contact ball bearing (Harris Vol. 1 ch. 2 notation)."""
    Dw_mm: float                 # ball diameter
    Z: int                       # number of balls
    dm_mm: float                 # pitch diameter
    f_i: float                   # inner groove radius ratio r_i / Dw
    f_o: float                   # outer groove radius ratio r_o / Dw
    alpha0_deg: float            # free (unloaded) contact angle
    ring: Material               # inner and outer ring material
    ball: Material
    designation: str = ""

    @classmethod
    def from_spec(cls, spec: BearingSpec, materials: tuple[Material, ...] = ()) -> "BearingGeometry":
        """From a `BearingSpec`, its materials resolved by name among a config's own `materials`
        first, then in the library (`analytic.materials.get_material`)."""
        return cls(Dw_mm=spec.ball_diameter_mm, Z=int(spec.ball_count),
                   dm_mm=spec.pitch_diameter_mm, f_i=spec.inner_groove_ratio,
                   f_o=spec.outer_groove_ratio, alpha0_deg=spec.contact_angle_free_deg,
                   ring=get_material(spec.ring_material, materials),
                   ball=get_material(spec.ball_material, materials),
                   designation=spec.designation)

    @classmethod
    def from_catalogue(cls, name: str) -> "BearingGeometry":
        """From `analytic.catalogue` (designation or alias)."""
        return cls.from_spec(get_entry(name).spec)

    @property
    def A0_mm(self) -> float:
        """Free distance of the groove curvature centres A0 = (f_i + f_o - 1) Dw (Harris Vol. 1 ch. 2)."""
        return (self.f_i + self.f_o - 1.0) * self.Dw_mm

    @property
    def radial_clearance_mm(self) -> float:
        """Free radial clearance Pd/2 = A0 (1 - cos alpha0) (Harris Vol. 1 ch. 2: cos alpha0 = 1 - Pd/(2 A0)), mm."""
        return self.A0_mm * (1.0 - np.cos(np.radians(self.alpha0_deg)))

    @property
    def E_star_MPa(self) -> float:
        """Contact modulus of ball on ring, MPa (`hertz.contact_modulus_MPa`)."""
        return float(hertz.contact_modulus_MPa(self.ring.E_MPa, self.ring.nu,
                                               self.ball.E_MPa, self.ball.nu))


@dataclass(frozen=True)
class ThermalGeometry:
    """Thermally grown bearing geometry at one set of part temperatures (arrays broadcast)."""
    A_T_mm: np.ndarray           # r_i + r_o - Dw (grown): centre distance at first contact
    Dw_mm: np.ndarray            # grown ball diameter
    f_i: np.ndarray              # grown r_i / grown Dw
    f_o: np.ndarray
    dm_mm: np.ndarray            # pitch diameter grown with the mean ring strain


def thermal_geometry(g: BearingGeometry, T_inner_ring_C=None, T_outer_ring_C=None,
                     T_ball_C=None, T_ref_C=20.0) -> ThermalGeometry:
    """Grown geometry: groove radii r = f Dw (1 + theta_ring), ball Dw (1 + theta_ball),
    A_T = r_i + r_o - Dw_ball (Harris & Kotzalas Vol. 1 ch. 2 with each part grown; seed 001 eq. 1 is the radial projection of the
    same statement), pitch diameter dm (1 + (theta_ir + theta_or)/2) (used only in the Hertz
    curvature, where it is a second-order effect).  theta = Material.thermal_strain (-)."""
    Tr = T_ref_C
    th_i = 0.0 if T_inner_ring_C is None else g.ring.thermal_strain(np.asarray(T_inner_ring_C, float), Tr)
    th_o = 0.0 if T_outer_ring_C is None else g.ring.thermal_strain(np.asarray(T_outer_ring_C, float), Tr)
    th_b = 0.0 if T_ball_C is None else g.ball.thermal_strain(np.asarray(T_ball_C, float), Tr)
    Dw = g.Dw_mm * (1.0 + np.asarray(th_b, float))
    r_i = g.f_i * g.Dw_mm * (1.0 + np.asarray(th_i, float))
    r_o = g.f_o * g.Dw_mm * (1.0 + np.asarray(th_o, float))
    dm = g.dm_mm * (1.0 + 0.5 * (np.asarray(th_i, float) + np.asarray(th_o, float)))
    return ThermalGeometry(A_T_mm=r_i + r_o - Dw, Dw_mm=Dw, f_i=r_i / Dw, f_o=r_o / Dw, dm_mm=dm)



def broadcast_geometry(tg: ThermalGeometry, shape) -> ThermalGeometry:
    """The grown geometry with every array broadcast to `shape` (read-only views)."""
    return ThermalGeometry(*(np.broadcast_to(np.asarray(getattr(tg, k), float), shape)
                             for k in ("A_T_mm", "Dw_mm", "f_i", "f_o", "dm_mm")))


def pair_thermal_geometry(g: BearingGeometry, T_inner_ring_C, T_outer_ring_C, T_ball_C,
                          T_ref_C: float, N: int) -> ThermalGeometry:
    """`thermal_geometry` of both bearings of a pair at N points, arrays (2, N); temperatures
    as `pair_array` takes them (None: T_ref)."""
    temps = [None if T is None else pair_array(T, N)
             for T in (T_inner_ring_C, T_outer_ring_C, T_ball_C)]
    return broadcast_geometry(thermal_geometry(g, *temps, T_ref_C=float(T_ref_C)), (2, N))


#: arrangement signs s_j of bearings A and B: "DB" back-to-back, "DF" face-to-face
SIGNS = {"DB": np.array([1.0, -1.0]), "DF": np.array([-1.0, 1.0])}


def pair_array(v, N: int) -> np.ndarray:
    """Broadcast an input to shape (2, N): scalars and (N,) arrays apply to both bearings; give
    per-bearing values as shape (2, N) or (2, 1)."""
    a = np.asarray(v, dtype=float)
    if a.ndim == 2:
        return np.broadcast_to(a, (2, N))
    return np.broadcast_to(a.reshape(1, -1) if a.ndim == 1 else a, (2, N))


def n_points(*vals) -> int:
    n = 1
    for v in vals:
        a = np.asarray(v)
        if a.ndim >= 1 and a.shape[-1] != 1:
            if n not in (1, a.shape[-1]):
                raise ValueError(f"inconsistent numbers of operating points: {n} and {a.shape[-1]}")
            n = a.shape[-1]
    return n
