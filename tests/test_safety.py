"""Safety: the film-parameter flag, ISO 76 static rating against an exact Hertz
calculation (its 4200 MPa basis) and against catalogue ratings, and the equivalent load."""
import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from analytic.safety import (film_parameter_flag, iso76_f0, required_static_safety,
                             static_equivalent_load_P0_N, static_load_rating_C0_N,
                             static_safety_factor, static_safety_from_contact_pressure)


def test_film_flag_and_static_safety_limits():
    assert film_parameter_flag(1.0).ok and not film_parameter_flag([2.0, 0.8]).ok
    assert film_parameter_flag([2.0, 0.8]).worst_index == 1
    assert static_safety_factor(6000.0, 1500.0) == pytest.approx(4.0)
    assert required_static_safety() == 3.0 and required_static_safety(3.0, 1.5) == 4.5


def hertz_max_pressure_MPa(Q_N, Rx_mm, Ry_mm, E_MPa, nu):
    """Exact Hertz maximum pressure of two identical-material bodies (Hamrock & Brewe 1983 /
    Harris & Kotzalas Vol. 1 ch. 6): ellipticity k from the curvature difference through the
    complete elliptic integrals, D_y = 2 (6 k^2 E(m) Q R / (pi E'))^(1/3),
    D_x = 2 (6 E(m) Q R / (pi k E'))^(1/3), p_max = 6 Q / (pi D_x D_y), E' = E/(1 - nu^2)."""
    F = (1 / Rx_mm - 1 / Ry_mm) / (1 / Rx_mm + 1 / Ry_mm)
    g = lambda k: ((k * k + 1) * ellipe(1 - k**-2) - 2 * ellipk(1 - k**-2)) / (  # noqa: E731
        (k * k - 1) * ellipe(1 - k**-2)) - F
    k = brentq(g, 1 + 1e-12, 1000)
    Em = ellipe(1 - k**-2)
    R = 1 / (1 / Rx_mm + 1 / Ry_mm)
    Ep = E_MPa / (1 - nu**2)
    Dy = 2 * (6 * k * k * Em * Q_N * R / (np.pi * Ep)) ** (1 / 3)
    Dx = 2 * (6 * Em * Q_N * R / (np.pi * k * Ep)) ** (1 / 3)
    return 6 * Q_N / (np.pi * Dx * Dy)


@pytest.mark.parametrize("gamma", np.round(np.arange(0.0, 0.4001, 0.01), 2))
def test_iso76_f0_is_4200MPa_at_the_most_loaded_contact(gamma):
    """At F_r = C0 (zero contact angle, Dw = 10 mm) the most loaded ball carries Stribeck's
    Q_max = 5 F_r / Z; with groove radii 0.52 Dw (inner) and 0.53 Dw (outer) and steel
    E = 207 GPa, nu = 0.3 (the basis of ISO 76, ISO/TR 10657), the larger of the inner and outer
    Hertz pressures is 4200 MPa (ISO 76 clause 3.1). Table values are rounded to 0.1, hence
    0.5 %."""
    Dw, Z = 10.0, 10
    Dpw = Dw / gamma if gamma > 0 else 1e9
    C0 = static_load_rating_C0_N(Z, Dw, Dpw, 0.0)
    Q = 5.0 * C0 / Z
    p_in = hertz_max_pressure_MPa(Q, Dw * (1 - gamma) / 2, 0.52 * Dw / 0.04, 207e3, 0.3)
    p_out = hertz_max_pressure_MPa(Q, Dw * (1 + gamma) / 2, 0.53 * Dw / 0.06, 207e3, 0.3)
    assert max(p_in, p_out) == pytest.approx(4200.0, rel=0.005)
    # and the pressure route to s0 gives s0 = 1 at the rating
    assert static_safety_from_contact_pressure(max(p_in, p_out)) == pytest.approx(1.0, rel=0.015)


@pytest.mark.parametrize("Z, Dw, Dpw, C0_catalogue", [
    (9, 7.94, 39.04, 7800.0),     # SKF 6205: geometry per the CWRU bearing data centre, C0 7.8 kN
    (8, 6.746, 28.50, 4750.0),    # SKF 6203: geometry per the CWRU bearing data centre, C0 4.75 kN
])
def test_static_rating_against_catalogue(Z, Dw, Dpw, C0_catalogue):
    """Deep groove ball bearings with published internal geometry (Case Western Reserve
    University bearing data centre: 6205-2RS ball 0.3126 in, pitch 1.537 in, 9 balls; 6203-2RS
    ball 0.2656 in, pitch 1.122 in, 8 balls) against the SKF catalogue C0; 3 % covers rounding
    of the geometry and the catalogue."""
    assert static_load_rating_C0_N(Z, Dw, Dpw) == pytest.approx(C0_catalogue, rel=0.03)


def test_f0_table_range_and_angular_contact():
    with pytest.raises(ValueError):
        iso76_f0(0.45)
    # angular contact: gamma uses Dw cos(alpha); C0 carries cos(alpha)
    C0 = static_load_rating_C0_N(12, 8.0, 45.0, 15.0)
    g = 8.0 * np.cos(np.radians(15.0)) / 45.0
    assert C0 == pytest.approx(iso76_f0(g) * 12 * 64.0 * np.cos(np.radians(15.0)), rel=1e-14)


def test_static_equivalent_load():
    """ISO 76: P0 = max(Fr, X0 Fr + Y0 Fa); deep groove X0 0.6, Y0 0.5; 25 deg X0 0.5, Y0 0.38."""
    assert static_equivalent_load_P0_N(1000.0, 0.0, 0.0) == 1000.0
    assert static_equivalent_load_P0_N(1000.0, 2000.0, 0.0) == pytest.approx(1600.0)
    assert static_equivalent_load_P0_N(0.0, 1000.0, 25.0) == pytest.approx(380.0)
    with pytest.raises(ValueError):
        static_equivalent_load_P0_N(1.0, 1.0, 60.0)
