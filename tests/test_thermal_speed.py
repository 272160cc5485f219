"""Thermal speed limits (analytic/thermal_speed.py): ISO 15312:2018 thermal reference speed and
DIN 732:2010 thermally permissible speed, against closed forms, the standards' own limits and a
maker's published value."""
from math import pi

import numpy as np
import pytest

from analytic.thermal_speed import (heat_balance_speed_rpm, reference_heat_flow_density_W_per_mm2,
                                    reference_heat_transfer_W_per_mm2_K, reference_surface_mm2,
                                    thermal_reference_speed, thermally_permissible_speed)


def test_viscous_only_balance_is_the_closed_form():
    """With no load term the balance (pi n/30e3) 1e-7 f0 (nu n)^(2/3) dm^3 = Q has the closed form
    n = (30e3 Q / (pi 1e-7 f0 nu^(2/3) dm^3))^(3/5)."""
    f0, nu, dm, Q = 2.0, 12.0, 46.0, 74.0
    expect = (30e3 * Q / (pi * 1e-7 * f0 * nu ** (2 / 3) * dm ** 3)) ** 0.6
    got = float(heat_balance_speed_rpm(f0, nu, dm, 0.0, Q))
    assert got == pytest.approx(expect, rel=1e-9)


def test_load_only_balance_is_the_closed_form():
    """With f0 = 0 the balance (pi n/30e3) M1 = Q gives n = 30e3 Q / (pi M1)."""
    assert float(heat_balance_speed_rpm(0.0, 12.0, 46.0, 50.0, 74.0)) == pytest.approx(
        30e3 * 74.0 / (pi * 50.0), rel=1e-9)


def test_reference_heat_flow_density_of_iso_15312():
    """16 kW/m^2 up to A_r = 50 000 mm^2; 16 (A_r/50 000)^-0.34 above: 16 * 2^-0.34 = 12.64 kW/m^2
    at 100 000 mm^2, continuous at the limit."""
    q = reference_heat_flow_density_W_per_mm2([1e3, 5e4, 1e5])
    assert q[0] == pytest.approx(16e-3, rel=1e-12) and q[1] == pytest.approx(16e-3, rel=1e-12)
    assert q[2] == pytest.approx(16e-3 * 2.0 ** -0.34, rel=1e-12)
    assert q[2] * 1e3 == pytest.approx(12.64, abs=0.005)


def test_din_732_at_the_reference_conditions_gives_the_reference_speed():
    """DIN 732 is ISO 15312's balance under actual conditions: with the reference f0r, load,
    viscosity and the heat given off at 70 C in 20 C ambient through k_q = q_r/50 K, f_n = 1."""
    ref = thermal_reference_speed(30.0, 62.0, 16.0, 14300.0, 2.0, 3.7e-4)
    k_q = reference_heat_transfer_W_per_mm2_K(ref.surface_mm2)
    Q = k_q * ref.surface_mm2 * (70.0 - 20.0)
    p = thermally_permissible_speed(ref.speed_rpm, 2.0, 12.0, 46.0, ref.load_torque_Nmm, Q)
    assert float(p.speed_ratio) == pytest.approx(1.0, rel=1e-9)
    assert float(p.K_L + p.K_P) == pytest.approx(1.0, rel=1e-9)   # K_L f^(5/3) + K_P f at f = 1


def test_din_732_speed_ratio_solves_its_equation():
    """Away from the reference state the speed ratio is the root of K_L f^(5/3) + K_P f = 1
    (DIN 732's form of the balance): more load and a thicker oil lower it below 1."""
    ref = thermal_reference_speed(30.0, 62.0, 16.0, 14300.0, 2.0, 3.7e-4)
    p = thermally_permissible_speed(ref.speed_rpm, 2.0, np.array([12.0, 46.0]), 46.0,
                                    np.array([ref.load_torque_Nmm, 4 * ref.load_torque_Nmm]),
                                    ref.heat_W)
    f = p.speed_ratio
    np.testing.assert_allclose(p.K_L * f ** (5 / 3) + p.K_P * f, 1.0, rtol=1e-9)
    assert f[0] == pytest.approx(1.0, rel=1e-9) and f[1] < 0.6


def test_reference_speed_of_a_schaeffler_7206_b():
    """Schaeffler (FAG) 7206-B, 30 x 62 x 16 mm, C0 = 14.3 kN, thermal reference speed
    13 000 r/min (Schaeffler product data, as listed at
    fgfa.com.cn/en/Angular_contact_ball_bearings/1164.html; no page number: an online table).
    With Palmgren's f1 at P1r = 0.05 C0 and the default oil-bath f0r = 2 the balance gives
    11 170 r/min. The maker's f0r and f1r are not published: n goes as f0r^-0.6 where the viscous
    term governs, so f0r between 1.3 and 2.7 (the ball-bearing spread of Palmgren's oil-bath
    table) moves n by about +-20 %: the tolerance, relative to the catalogue value, covers that."""
    ref = thermal_reference_speed(30.0, 62.0, 16.0, 14300.0, 2.0, 0.001 * 0.05 ** 0.33)
    assert ref.surface_mm2 == pytest.approx(reference_surface_mm2(30.0, 62.0, 16.0))
    assert ref.heat_W == pytest.approx(16e-3 * pi * 16 * 92, rel=1e-12)
    assert ref.speed_rpm == pytest.approx(13000.0, rel=0.20)
