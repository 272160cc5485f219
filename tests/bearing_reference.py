"""Reference values for the bearing tests, written out independently of analytic/bearing/."""
import numpy as np

from analytic import hertz


def kn_direct(g, alpha, Dw=None, dm=None, f_i=None, f_o=None):
    """K_n from the Hertz primitives (Harris Vol. 1 ch. 2 radii, exact Hertz stiffness of each
    contact, the two in series, ch. 7), not from bearing.contact_stiffness."""
    Dw = g.Dw_mm if Dw is None else Dw
    dm = g.dm_mm if dm is None else dm
    f_i = g.f_i if f_i is None else f_i
    f_o = g.f_o if f_o is None else f_o
    Es = hertz.contact_modulus_MPa(g.ring.E_MPa, g.ring.nu, g.ball.E_MPa, g.ball.nu)
    deg = np.degrees(alpha)
    Ki = hertz.contact_stiffness_N_per_mm15(*hertz.ball_raceway_radii_mm(Dw, dm, deg, f_i, "inner"), Es)
    Ko = hertz.contact_stiffness_N_per_mm15(*hertz.ball_raceway_radii_mm(Dw, dm, deg, f_o, "outer"), Es)
    return hertz.series_stiffness_N_per_mm15(Ki, Ko)


def flat(state) -> dict:
    """Every array of a `bearing.PairState` under one name, for element-wise comparisons between
    solver paths: "preload_N", "axial_force_N[A]", "inner.p_max_MPa[B]", "radial.rho_mm",
    "radial.ball_loads_N[A]" (Z, N), ... plus "loaded_contact_angle_deg"."""
    out = {}

    def walk(obj, prefix):
        for name in obj.__dataclass_fields__:
            v = getattr(obj, name)
            if v is None:
                continue
            if hasattr(v, "__dataclass_fields__"):
                walk(v, f"{prefix}{name}.")
            elif np.ndim(v) >= 2 and np.shape(v)[0] == 2:
                out[f"{prefix}{name}[A]"], out[f"{prefix}{name}[B]"] = v[0], v[1]
            else:
                out[f"{prefix}{name}"] = np.asarray(v)
    walk(state, "")
    out["loaded_contact_angle_deg"] = state.loaded_contact_angle_deg
    return out


def seed001_axial_contacts():
    """Seed 001's bearing under a pure axial load (50 and 200 N, every ball alike) at 3500 and
    9000 rpm with quasi-dynamic balls: (asm, geometry, speed_rpm, every ball's contacts, the first
    ball's contacts as a representative one, the oil, its viscosity mm^2/s at 20 and 40 C), for
    the tests that count the balls two ways (`bearing`'s every ball against the pair route's Z
    times one)."""
    from analytic.bearing import BearingGeometry
    from analytic.bearing.single import solve_single
    from analytic.friction.pair import BearingContacts, single_bearing_contacts
    from analytic.torque import ContactInput
    from studies.model.config import load_shipped

    asm = load_shipped("seed001")
    g = BearingGeometry.from_spec(asm.bearing, asm.materials)
    speed = np.array([3500.0, 9000.0])
    st = solve_single(g, axial_load_N=np.array([50.0, 200.0]), speed_rpm=speed,
                      ball_model="quasi_dynamic")
    every = single_bearing_contacts(st)

    def first(k):
        return ContactInput(*(np.asarray(getattr(k, f))[0]
                              for f in ("Q_N", "a_mm", "b_mm", "E_ell", "Rx_mm")))

    one = BearingContacts(first(every.inner), first(every.outer), every.alpha_inner_rad[0],
                          every.alpha_outer_rad[0], every.axial_force_N, every.radial_force_N)
    oil = asm.oil()
    return asm, g, speed, every, one, oil, oil.nu_mm2_s(np.array([20.0, 40.0]))
