"""Reference values for the bearing tests, written out independently of analytic/bearing.py."""
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
