"""The speed exponents of `bench --friction` (studies/bench/bench_friction.py) against the laws'
own exponents in closed form: Palmgren's (nu n)^(2/3) gives 2/3 at a fixed viscosity (Harris &
Kotzalas Vol. 2 ch. 2), the EHL rolling force U^0.66 gives 0.66 (Houpert 2002), and SKF's
rolling term G_rr (nu n)^0.6 tends to 0.6 at low speed, where its reductions phi_ish, phi_rs -> 1
and the centrifugal load F_g -> 0 (SKF catalogue)."""
import numpy as np

from analytic.friction.skf2004 import skf2004_torque
from studies.bench import bench_friction as bf


def test_exponents_are_the_laws_own():
    for nu in bf.VISCOSITIES_MM2_S:
        e = bf.exponents(nu)
        assert abs(e["palmgren"] - 2.0 / 3.0) < 1e-12
        assert abs(e["ehl_rolling (one contact)"] - 0.66) < 1e-12


def test_skf_rolling_exponent_tends_to_0_6_at_low_speed():
    n = np.array([1.0, 2.0])
    t = skf2004_torque(bf.BORE_MM, bf.OUTSIDE_MM, 0.0, bf.AXIAL_N, n, 5.0)
    assert abs(bf.local_exponents(n, t.rolling_Nmm)[0] - 0.6) < 1e-4
