"""The equilibrium state of a bearing pair: one typed result, built in one place (`pair_state`) by
both solvers. Per-bearing arrays have shape (2, N): bearing A first, then B. Units in the names."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic import hertz
from analytic.bearing.contact import ContactStiffness
from analytic.bearing.geometry import BearingGeometry


@dataclass(frozen=True)
class ContactEllipses:
    """Hertz contact of one raceway side (inner or outer) in each bearing, (2, N)."""
    a_mm: np.ndarray             # semi-major (transverse) axis
    b_mm: np.ndarray             # semi-minor (rolling) axis
    p_max_MPa: np.ndarray        # maximum contact pressure
    E_ell: np.ndarray            # complete elliptic integral of the second kind (-)
    Rx_mm: np.ndarray            # effective radius along the rolling direction


@dataclass(frozen=True)
class RadialLoadState:
    """What the combined-load solver adds (`combined.solve_pair_combined`).  rho_mm and the
    radial stiffness refer to the mid-point between the two bearings' ball planes (where the
    radial load acts); the moment is taken about it."""
    rho_mm: np.ndarray                       # (N,) rotor radial displacement along the load
    radial_force_N: np.ndarray               # (2, N) radial load share of each bearing
    max_ball_load_N: np.ndarray              # (2, N) largest ball load of each bearing
    loaded_zone: np.ndarray                  # (2, N) fraction of balls in contact
    radial_stiffness_N_per_um: np.ndarray    # (N,) dF_r/drho at constant axial load (and moment)
    tilt_rad: np.ndarray                     # (N,) rotor tilt (0 without a bearing span)
    bearing_rho_mm: np.ndarray               # (2, N) rotor radial displacement at each ball plane
    bearing_moment_Nmm: np.ndarray           # (2, N) moment each bearing carries about its ball plane
    moment_stiffness_Nmm_per_mrad: np.ndarray  # (N,) dM/dtheta, Fa and Fr held (NaN: no tilt DOF)
    max_contact_pressure_MPa: np.ndarray     # (2, N) over every ball and both contacts of a bearing
    ball_loads_N: np.ndarray | None = None   # (2, Z, N), ball k at psi_k = 2 pi k / Z
    ball_contact_angles_deg: np.ndarray | None = None
    #: every ball's inner and outer Hertz contact, (2, Z, N) (the torque sums over the balls)
    ball_inner: ContactEllipses | None = None
    ball_outer: ContactEllipses | None = None
    #: quasi-dynamic balls: every ball's outer contact load and angle (the fields above are the
    #: inner contact's); None with quasi-static balls (inner = outer)
    ball_loads_outer_N: np.ndarray | None = None
    ball_contact_angles_outer_deg: np.ndarray | None = None
    #: quasi-dynamic balls: True where the outer raceway controls the ball (2, Z, N)
    ball_outer_control: np.ndarray | None = None

    @property
    def unequal_balls(self) -> np.ndarray:
        """(N,) bool: the balls of a bearing carry different loads (radial displacement or tilt)."""
        return (self.rho_mm != 0.0) | (self.tilt_rad != 0.0)


@dataclass(frozen=True)
class PairState:
    """Equilibrium of a preloaded pair at N operating points.

    Under a radial load the per-bearing ball quantities (ball load, deflection, contact angle,
    ellipses) refer to the most loaded ball of that bearing, and `radial` is set."""
    preload_N: np.ndarray                    # (N,) min(F_A, F_B); 0 when the preload is lost
    axial_force_N: np.ndarray                # (2, N) axial force carried by each bearing
    contact_angle_deg: np.ndarray            # (2, N) (unloaded: angle of the groove-centre line)
    ball_load_N: np.ndarray                  # (2, N)
    delta_mm: np.ndarray                     # (2, N) inner + outer contact deformation
    inner: ContactEllipses
    outer: ContactEllipses
    max_contact_pressure_MPa: np.ndarray     # (N,) over every ball and both contacts
    axial_stiffness_N_per_um: np.ndarray     # (2, N) per bearing, with the preload path in series
    pair_axial_stiffness_N_per_um: np.ndarray  # (N,) of the pair against an external axial load
    preload_lost: np.ndarray                 # (N,) bool
    x_mm: np.ndarray                         # (N,) rotor axial position
    preload_offset_mm: np.ndarray            # (N,) position-preload offset e (NaN for a spring)
    approach_mm: np.ndarray                  # (2, N) axial approach of each bearing
    converged: np.ndarray                    # (N,) bool: every root finder of the row converged
    radial: RadialLoadState | None = None
    #: quasi-dynamic balls (`dynamic.DynamicContacts`): inner and outer contacts apart
    dynamic: object | None = None

    @property
    def loaded_contact_angle_deg(self) -> np.ndarray:
        """Contact angle of the more loaded bearing, (N,)."""
        F = self.axial_force_N
        return np.where(F[0] >= F[1], self.contact_angle_deg[0], self.contact_angle_deg[1])


def contact_ellipses(g: BearingGeometry, cs: ContactStiffness, Q_N: np.ndarray,
                     side: int) -> ContactEllipses:
    """Hertz ellipses of raceway side `side` (0 inner, 1 outer) at ball loads Q_N (N), any shape
    that `cs` broadcasts with (`hertz.hertz_from_kappa`, Harris Vol. 1 ch. 6)."""
    hc = hertz.hertz_from_kappa(Q_N, cs.R_mm[side], g.E_star_MPa, cs.kappa[side], cs.K_ell[side],
                                cs.E_ell[side])
    shape = np.shape(hc.a_mm)
    return ContactEllipses(hc.a_mm, hc.b_mm, hc.p_max_MPa, np.broadcast_to(cs.E_ell[side], shape),
                           np.broadcast_to(cs.Rx_mm[side], shape))


def pair_state(*, F_N, alpha_rad, Q_N, delta_mm, inner: ContactEllipses, outer: ContactEllipses,
               max_contact_pressure_MPa, k_bearing_N_per_mm, k_pair_N_per_mm, lost, x_mm,
               offset_mm, approach_mm, converged, radial: RadialLoadState | None = None,
               dynamic=None) -> PairState:
    """The one constructor of `PairState` from a solver's final state (per-bearing (2, N) arrays;
    stiffnesses in N/mm, reported in N/um)."""
    F_N = np.asarray(F_N)
    return PairState(
        preload_N=np.where(lost, 0.0, np.minimum(F_N[0], F_N[1])), axial_force_N=F_N,
        contact_angle_deg=np.degrees(alpha_rad), ball_load_N=np.asarray(Q_N),
        delta_mm=np.asarray(delta_mm), inner=inner, outer=outer,
        max_contact_pressure_MPa=np.asarray(max_contact_pressure_MPa),
        axial_stiffness_N_per_um=1e-3 * np.asarray(k_bearing_N_per_mm),
        pair_axial_stiffness_N_per_um=1e-3 * np.asarray(k_pair_N_per_mm),
        preload_lost=np.asarray(lost, bool), x_mm=np.asarray(x_mm),
        preload_offset_mm=np.asarray(offset_mm), approach_mm=np.asarray(approach_mm),
        converged=np.asarray(converged, bool), radial=radial, dynamic=dynamic)


def _combine(fn, first, *others):
    """Apply fn to corresponding arrays of dataclass states (recursively; None stays None)."""
    if first is None:
        return None
    if hasattr(first, "__dataclass_fields__"):
        return type(first)(**{f: _combine(fn, getattr(first, f), *(getattr(o, f) for o in others))
                              for f in first.__dataclass_fields__})
    return fn(first, *others)


def concatenate_states(states: list[PairState]) -> PairState:
    """States of consecutive blocks of points joined into one (along the last axis)."""
    return _combine(lambda *a: np.concatenate(a, axis=-1), *states)


def take_rows(state: PairState, rows: np.ndarray) -> PairState:
    """The state whose point i is point rows[i] of `state` (every array, along the last axis)."""
    return _combine(lambda a: np.asarray(a)[..., rows], state)


def with_rows(state: PairState, rows: np.ndarray, sub: PairState) -> PairState:
    """A copy of `state` whose points `rows` are replaced by the points of `sub` (both with the
    same optional parts set)."""
    def put(a, b):
        out = np.array(a, copy=True)
        out[..., rows] = b
        return out
    return _combine(put, state, sub)
