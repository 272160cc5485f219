"""A fit whose response is even about a parameter's off value (`fitspec.even`) is restarted off
it (`studies.diagnosis.fitting.restart_even`): checked on data made by an independent closed
form, not by the tool's pair model.

The closed form: a symmetric pair's friction torque taken as proportional to the magnitude of
each bearing's load vector (axial preload Pa, radial share F/2), T = 2 c sqrt(Pa^2 + (F/2)^2),
plus a tilt term b M^2 (N mm): even in the radial load F and in the moment M, as the pair's
5-DOF model is (its mirror image and half a turn about the axis). Rows step Pa through
7 / 15 / 30 N as the benchmark's flywheel rig does, so that F and M are separately
identifiable. No noise: the fit must recover the hidden F and M to the optimiser's tolerance.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from studies.diagnosis import fitspec
from studies.diagnosis.core import Space
from studies.diagnosis.fitting import restart_even
from studies.diagnosis.ladder import UnloggedLoad
from studies.diagnosis.problem import Problem

C_NMM_PER_N = 0.05          # torque per unit load magnitude (N mm / N), the toy's constant
B_NMM_PER_NMM2 = 2e-9       # tilt torque per moment squared (N mm / (N mm)^2)
F_TRUE_N, M_TRUE_NMM = 30.0, 3000.0
SIGMA_NMM = 1e-3            # the residuals' scale (N mm)


def torque_Nmm(Pa_N, F_N, M_Nmm):
    """The toy's closed form (module docstring), N mm."""
    return 2.0 * C_NMM_PER_N * np.sqrt(Pa_N ** 2 + (0.5 * F_N) ** 2) + B_NMM_PER_NMM2 * M_Nmm ** 2


class Toy:
    """The least a fit needs of a `Problem`: the residuals at a point of its Space."""
    fit = Problem.fit          # the engine's own bounded least squares

    def __init__(self):
        self.Pa = np.array([7.0, 15.0, 30.0] * 10)
        self.N = self.Pa.size
        self.y = torque_Nmm(self.Pa, F_TRUE_N, M_TRUE_NMM)
        self.nuisance = SimpleNamespace(names=())
        self.conditions, self.T_ref_C = {}, 20.0
        self.e = UnloggedLoad(C0_N=1000.0, span_mm=100.0)
        e = self.e
        ps = list(e.parameters)
        self.space = Space([(e.name, p) for p in ps], {e.name: dict(e.off)}, [],
                           np.array([e.off[p] for p in ps]), np.array([e.scale[p] for p in ps]),
                           np.array([(e.bounds[p][0] - e.off[p]) / e.scale[p] for p in ps]),
                           np.array([(e.bounds[p][1] - e.off[p]) / e.scale[p] for p in ps]))

    def eval(self, space, u):
        effects, _ = space.unpack(space.clip(u))
        p = effects[self.e.name]
        pred = torque_Nmm(self.Pa, p["radial_load_N"], p["moment_Nmm"])
        return (pred - self.y) / SIGMA_NMM, {"torque_Nmm": pred}


def test_unlogged_load_declared_even():
    assert set(fitspec.even(UnloggedLoad(1000.0, 100.0))) == {"radial_load_N", "moment_Nmm"}


def test_fit_at_zero_load_is_restarted_and_finds_the_load():
    pb = Toy()
    sp = pb.space
    # from F = 0 (the moment near its value) the engine's gradient fit stops at F = 0: the
    # chi-square's derivative in F vanishes there whatever the data
    stuck = pb.fit(sp, sp.to_u([0.0, 2500.0]))
    F_stuck, M_stuck = sp.values(stuck.u)
    assert F_stuck < 1e-3 * F_TRUE_N and stuck.chi2 > 1e3
    f = restart_even(pb, pb.e, stuck)
    F, M = sp.values(f.u)
    # noise-free data of the closed form: recovered to 1e-4 of the hidden values
    assert abs(F - F_TRUE_N) < 1e-4 * F_TRUE_N
    assert abs(abs(M) - M_TRUE_NMM) < 1e-4 * M_TRUE_NMM
    assert f.chi2 < 1e-6 * stuck.chi2


def test_fit_away_from_off_is_kept():
    pb = Toy()
    sp = pb.space
    f0 = pb.fit(sp, sp.to_u([20.0, 2000.0]))
    assert restart_even(pb, pb.e, f0) is f0
