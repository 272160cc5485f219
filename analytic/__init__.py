"""Analytic half of bearingfem: Lamé fits, Hertz contact, bearing pair equilibrium, torque,
lubrication, lumped thermal network and the material library. Units: mm, N, MPa, s, C."""
