"""Axisymmetric finite-element half of bearingfem (scikit-fem): thermo-elasticity with fits as
contact, steady conduction, unit-solution superposition, post-processing and field images.
Units: mm, N, MPa, s, C."""
