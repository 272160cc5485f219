"""Lubrication: Walther law against datasheet points it was not fitted to, the slope-factor
definition, the library's provenance, Hamrock-Dowson scaling laws and units (SI recomputation),
the ellipticity approximation against the exact elliptic-integral ellipticity, contact kinematics,
film parameter and GB/T 28878.2 regimes, and the real-data viscosity study."""
import csv
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from analytic import lubrication as lub
from analytic.lubrication import (ball_raceway_radii_mm, csv_sources, dynamic_viscosity_Pa_s,
                                  ellipticity_hamrock_dowson, entrainment_speed_mm_s,
                                  film_parameter, fit_vogel, fit_walther, get_lubricant,
                                  hamrock_dowson_film, lubricant_library, lubrication_regime,
                                  reduced_modulus_MPa, walther_transform)

# --------------------------------------------------------------------------- Walther


def test_two_point_walther_reproduces_its_points():
    law = get_lubricant("Fomblin Z25").walther([40, 100])
    assert law.nu_mm2_s([40.0, 100.0]) == pytest.approx([157.0, 49.0], rel=1e-12)


def test_two_point_walther_predicts_the_20C_datasheet_points():
    """Fitted to the 40 and 100 C points only, the law is compared with the 20 C datasheet values
    (ESTL2018 Table 8): Fomblin Z25 263 mm^2/s is met within 1 % (it gives +0.4 %); Fomblin Z60
    (600) and Nye 2001a (297) are over-predicted by about 5 %: the tolerance is what the law
    honestly gives 20 K outside its fitted range."""
    z25 = get_lubricant("Z25").walther([40, 100]).nu_mm2_s(20.0)
    assert z25 == pytest.approx(263.0, rel=0.01)
    for name, measured in (("Z60", 600.0), ("Nye 2001a", 297.0)):
        pred = get_lubricant(name).walther([40, 100]).nu_mm2_s(20.0)
        assert 1.0 < pred / measured < 1.06


def test_least_squares_walther_has_orthogonal_residuals():
    """Least squares in the transformed variables: residuals orthogonal to (1, log10 T_K)."""
    T = np.array([20.0, 40.0, 100.0])
    nu = np.array([297.0, 108.0, 14.6])
    law = fit_walther(T, nu)
    x = np.log10(T + 273.15)
    r = walther_transform(nu) - (law.A - law.B * x)
    assert abs(r.sum()) < 1e-13 and abs((r * x).sum()) < 1e-13
    assert np.abs(r).max() > 1e-4          # three real points are not collinear
    with pytest.raises(ValueError):
        fit_walther([40.0], [100.0])


def test_slope_factor_keeps_40C_and_scales_the_walther_slope():
    law = get_lubricant("X-2000").walther([40, 100])
    T = np.array([-40.0, 0.0, 40.0, 100.0])
    x = np.log10(T + 273.15)
    for s in (0.8, 1.0, 1.25):
        nu_s = law.nu_mm2_s(T, slope_factor=s)
        assert nu_s[2] == pytest.approx(107.0, rel=1e-12)
        slope = np.diff(walther_transform(nu_s)) / np.diff(x)
        assert slope == pytest.approx(-s * law.B * np.ones(3), rel=1e-10)
    assert law.nu_mm2_s(-40.0, 1.2) > law.nu_mm2_s(-40.0) > law.nu_mm2_s(-40.0, 0.8)
    with pytest.raises(ValueError):
        law.nu_mm2_s(0.0, slope_factor=0.0)


def test_vogel_law_passes_through_three_points_or_refuses():
    T, nu = [20.0, 40.0, 100.0], [297.0, 108.0, 14.6]
    law = fit_vogel(T, nu)
    assert law.nu_mm2_s(T) == pytest.approx(nu, rel=1e-9)
    assert 0 < law.T0_K < 293.15
    # Fomblin Z60's three points curve the other way in ln(nu) vs 1/T: no VFT law exists
    with pytest.raises(ValueError):
        fit_vogel([20.0, 40.0, 100.0], [600.0, 355.0, 98.0])

# --------------------------------------------------------------------------- library


def test_library_is_read_from_the_project_copy_with_sources():
    assert lub.DATA_CSV.resolve().is_relative_to(Path(lub.__file__).resolve().parent)
    src = csv_sources()
    for key in ("ESTL2018", "BESSETTE1997", "SNC2018", "JPL2022", "METIMAGE2020"):
        assert key in src and len(src[key]) > 40
    with open(lub.DATA_CSV) as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    assert {r["source"] for r in rows} <= set(src)      # every row's source is cited
    lib = lubricant_library()
    assert len(lib) == len({r["lubricant"] for r in rows})
    x2000 = get_lubricant("Pennzane SHF X-2000")
    assert x2000.density_kg_m3 == 840.0 and x2000.pour_point_C == -55.0
    assert x2000.family == "MAC" and get_lubricant("815Z").family == "PFPE"
    with pytest.raises(ValueError):      # one point only: no Walther law from the project data
        get_lubricant("Brayco 815Z").walther()
    with pytest.raises(KeyError):
        get_lubricant("Krytox 143AC")


def test_dynamic_viscosity_units():
    """100 mm^2/s = 1e-4 m^2/s; times 1000 kg/m^3 = 0.1 Pa*s (unit identity)."""
    assert dynamic_viscosity_Pa_s(100.0, 1000.0) == pytest.approx(0.1, rel=1e-14)
    z25 = get_lubricant("Z25")
    assert z25.eta_Pa_s(40.0) == pytest.approx(z25.nu_mm2_s(40.0) * 1e-6 * 1850.0, rel=1e-14)

# --------------------------------------------------------------------------- Hamrock-Dowson

BASE = dict(Rx_mm=2.0, Ry_mm=30.0, E_reduced_MPa=228e3, eta0_Pa_s=0.1, alpha_per_Pa=1.5e-8,
            entrainment_speed_mm_s=2000.0, load_N=50.0)


def test_hamrock_dowson_scaling_laws():
    """h_min ~ u^0.68 eta^0.68 alpha^0.49 w^-0.073 and h_c ~ u^0.67 alpha^0.53 w^-0.067 at fixed
    geometry (exponents of Hamrock & Dowson 1977; checked as ratios, exact to round-off)."""
    f0 = hamrock_dowson_film(**BASE)
    for key, exp_min, exp_c in (("entrainment_speed_mm_s", 0.68, 0.67), ("eta0_Pa_s", 0.68, 0.67),
                                ("alpha_per_Pa", 0.49, 0.53), ("load_N", -0.073, -0.067)):
        f = hamrock_dowson_film(**{**BASE, key: 2 * BASE[key]})
        assert f.h_min_um / f0.h_min_um == pytest.approx(2**exp_min, rel=1e-12)
        assert f.h_central_um / f0.h_central_um == pytest.approx(2**exp_c, rel=1e-12)


def test_hamrock_dowson_units_against_an_SI_recomputation():
    """Recompute with every quantity in SI (m, Pa, Pa*s, m/s, N) written out by hand: the mm/MPa
    implementation must agree to round-off (catches any unit slip)."""
    Rx, Ry, Ep = 2.0e-3, 30.0e-3, 228e9
    eta, alpha, u, w = 0.1, 1.5e-8, 2.0, 50.0
    U, G, W = eta * u / (Ep * Rx), alpha * Ep, w / (Ep * Rx**2)
    k = 1.03 * (Ry / Rx) ** 0.64
    h_min_m = Rx * 3.63 * U**0.68 * G**0.49 * W**-0.073 * (1 - np.exp(-0.68 * k))
    h_c_m = Rx * 2.69 * U**0.67 * G**0.53 * W**-0.067 * (1 - 0.61 * np.exp(-0.73 * k))
    f = hamrock_dowson_film(**BASE)
    assert f.h_min_um == pytest.approx(h_min_m * 1e6, rel=1e-12)
    assert f.h_central_um == pytest.approx(h_c_m * 1e6, rel=1e-12)
    assert (f.U, f.G, f.W) == pytest.approx((U, G, W), rel=1e-12)


def exact_ellipticity(ratio):
    """Hertz ellipticity k = a/b from Ry/Rx through the complete elliptic integrals:
    (Ry - Rx)/(Ry + Rx) = [(k^2 + 1) E(m) - 2 K(m)] / [(k^2 - 1) E(m)], m = 1 - 1/k^2
    (Harris & Kotzalas Vol. 1 ch. 6)."""
    F = (ratio - 1) / (ratio + 1)
    g = lambda k: ((k * k + 1) * ellipe(1 - k**-2) - 2 * ellipk(1 - k**-2)) / (  # noqa: E731
        (k * k - 1) * ellipe(1 - k**-2)) - F
    return brentq(g, 1 + 1e-9, 500)


def test_ellipticity_approximation_against_exact_elliptic_integrals():
    """1.03 (Ry/Rx)^0.64 vs the exact ellipticity over the fitted range k <= 8 (Ry/Rx <= 25):
    within 3.1 % (the 1.03 prefactor alone is the 3 % at a circular contact)."""
    for ratio in (1.0 + 1e-6, 1.5, 2, 3, 5, 10, 15, 25):
        assert ellipticity_hamrock_dowson(1.0, ratio) == pytest.approx(exact_ellipticity(ratio),
                                                                       rel=0.031)


def test_contact_radii_and_entrainment_from_curvature_and_cage_kinematics():
    """Zero contact angle: 1/Rx = 2/Dw + 2/d_i (inner, convex race, d_i = dm - Dw) and
    2/Dw - 2/d_o (outer, d_o = dm + Dw); 1/Ry = 2/Dw - 1/(f Dw). Entrainment speed = inner race
    speed relative to the cage, omega_cage = omega_i (1 - Dw/dm)/2 (Harris & Kotzalas ch. 10)."""
    Dw, dm, f = 8.0, 40.0, 0.52
    Rx_i, Ry_i = ball_raceway_radii_mm(Dw, dm, 0.0, f, "inner")
    Rx_o, _ = ball_raceway_radii_mm(Dw, dm, 0.0, f, "outer")
    assert 1 / Rx_i == pytest.approx(2 / Dw + 2 / (dm - Dw), rel=1e-13)
    assert 1 / Rx_o == pytest.approx(2 / Dw - 2 / (dm + Dw), rel=1e-13)
    assert 1 / Ry_i == pytest.approx(2 / Dw - 1 / (f * Dw), rel=1e-13)
    n = 3000.0
    wi = 2 * np.pi * n / 60
    wc = wi * (1 - Dw / dm) / 2
    assert entrainment_speed_mm_s(n, Dw, dm, 0.0) == pytest.approx((wi - wc) * (dm - Dw) / 2,
                                                                    rel=1e-13)


def test_reduced_modulus_definition():
    """E' = E/(1 - nu^2) for two identical bodies (Hamrock & Dowson's E' = 2 E*)."""
    assert reduced_modulus_MPa(200e3, 0.3, 200e3, 0.3) == pytest.approx(200e3 / 0.91, rel=1e-14)

# --------------------------------------------------------------------------- lambda and regime


def test_film_parameter_and_regimes():
    assert film_parameter(0.3, 0.3, 0.4) == pytest.approx(0.6, rel=1e-14)
    lam = [0.5, 0.999, 1.0, 2.99, 3.0, 9.99, 10.0, 50.0]
    assert list(lubrication_regime(lam)) == ["boundary", "boundary", "mixed", "mixed",
                                              "partial_ehl", "partial_ehl", "full_film",
                                              "full_film"]
    assert lubrication_regime(0.2) == "boundary"

# --------------------------------------------------------------------------- real-data study


def test_lubricant_viscosity_study(tmp_path):
    """Runs the study and checks the physics statement about the data: for the MAC oils (where
    the CSV has a sister-oil point below 40 C) the extended model's held-out error is smaller
    than the two-point Walther fit's; for the PFPE pair (Fomblin Z25 as analog of Brayco 815Z)
    it is not, and the report says so."""
    from studies.validation.lubricant_viscosity import run

    run(tmp_path)
    for name in ("predictions.csv", "leave_one_out.csv", "viscosity_temperature.png", "report.md"):
        assert (tmp_path / name).exists() and (tmp_path / name).stat().st_size > 0
    with open(tmp_path / "leave_one_out.csv") as fh:
        rows = {(r["lubricant"], float(r["temperature_C"])): r
                for r in csv.DictReader(line for line in fh if not line.startswith("#"))}
    x2000 = rows[("Pennzane SHF X-2000 (base MAC)", -40.0)]
    assert float(x2000["measured_mm2_s"]) == 80500.0
    assert abs(float(x2000["extended_error_pct"])) < abs(float(x2000["two_point_error_pct"]))
    nye = rows[("Nye 2001a (Pennzane MAC)", 20.0)]
    assert abs(float(nye["extended_error_pct"])) < abs(float(nye["two_point_error_pct"]))
    brayco = rows[("Brayco 815Z (PFPE; base oil of Braycote 600EF/601EF)", -54.0)]
    assert abs(float(brayco["extended_error_pct"])) >= abs(float(brayco["two_point_error_pct"]))
    report = (tmp_path / "report.md").read_text()
    assert "no gain" in report.lower()
