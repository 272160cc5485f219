"""Line-to-line fits (0 / 0 um) settle in the contact solver at every temperature.

A one-material stack at a uniform temperature expands as one similar body: no part presses on
another, so both fits carry zero pressure at every temperature (the Lame closed form of a fit
with zero interference and no thermal mismatch, `analytic.lame.fit_pressure_MPa`: p = 0) and the
position preload is the assembled one. Its free gaps are differences of displacements that
cancel to round-off; before `fem.solver.ContactTolerance` the active set cycled on that noise
("contact active set did not settle in 100 iterations" at 0, 40 and 60 C).
"""
import tomllib

import numpy as np
import pytest

from analytic.lame import fit_pressure_MPa
from analytic.materials import get_material
from fem.solver import (GAP_ROUNDOFF_REL, ContactTolerance, SolveError, Superposition,
                        load_columns)
from studies.model.config import CONFIG_DIR, assembly_from_dict
from studies.model.pipeline import Pipeline, table_inputs

MATERIAL = "440C"
#: 1 K steps over the issue's range
T_C = np.arange(-80.0, 80.5, 1.0)


def _one_material(inner_um: float = 0.0, outer_um: float = 0.0):
    """The template's pair with every part (rings and balls too) in 440C and the given fits."""
    raw = tomllib.loads((CONFIG_DIR / "template.toml").read_text())
    for sec in raw.values():
        for key in ("material", "ring_material", "ball_material"):
            if isinstance(sec, dict) and key in sec:
                sec[key] = MATERIAL
    raw["fits"]["inner_interference_um"] = inner_um
    raw["fits"]["outer_interference_um"] = outer_um
    return assembly_from_dict(raw, "one-material template")


@pytest.fixture(scope="module")
def line_to_line():
    """The pipeline of the 0 / 0 um stack on a mesh coarsened 2x (the set-up is the cost)."""
    return Pipeline(_one_material(), mesh_factor=2.0)


def _uniform_states(pl, T):
    """(theta, delta, omega^2) of the stack at uniform temperatures T (C), at rest, 0 / 0 fits."""
    sup = pl.sup
    theta = pl.fe_stage.thetas(table_inputs(pl.asm, {"T_ambient_C": T, "speed_rpm": 0 * T}))
    return theta, np.zeros((T.size, sup.n_fits)), np.zeros(T.size)


def test_zero_fits_settle_one_state_at_a_time_and_all_together(line_to_line):
    """Every 1 K from -80 to 80 C (and +-0.001 C about 0) settles, alone and as one call, with
    zero contact force: no pair force above the round-off force floor of its state."""
    pl = line_to_line
    sup = pl.sup
    T = np.concatenate([T_C, [-0.001, 0.001]])
    theta, delta, w2 = _uniform_states(pl, T)
    together = sup.evaluate(theta, delta, w2)
    for i in range(T.size):
        alone = sup.evaluate(theta[i:i + 1], delta[i:i + 1], w2[i:i + 1])
        np.testing.assert_array_equal(alone.force_N[0], together.force_N[i])
    C = np.hstack([load_columns(theta, w2), delta])
    tol = ContactTolerance.of(np.zeros((T.size, sup.n_pairs)), C, sup._column_reach_mm,
                              sup._stiffest_mm_per_N)
    assert np.all(np.abs(together.force_N) <= tol.force_N[:, None])
    # the tolerance is round-off, not physics: far below the gap of a 0.001 um fit
    assert np.all(tol.accept_gap_mm < 1e-3 * 0.5e-3)
    assert GAP_ROUNDOFF_REL <= 1e-10


def test_zero_fits_zero_pressure_and_assembled_preload(line_to_line):
    """The whole route, 161 rows at rest: fit pressures are the Lame closed form's 0 MPa (to
    1e-9 of the Lame pressure of a 1 um diametral interference at the inner fit), and the
    preload is the assembled one to alpha |T - T_ref| of it, relative: a one-material stack at
    a uniform temperature is the assembled stack scaled by 1 + alpha dT (stress-free), whose
    position preload changes only by that order (exactly (1 + alpha dT)^2 for a similar body;
    the bearing model holds its Hertz constants and offset at their assembled values: measured
    0.33 alpha dT). Smooth in T: no round-off contact status in its second differences."""
    pl = line_to_line
    asm = pl.asm
    res = pl.run(table_inputs(asm, {"T_ambient_C": T_C, "speed_rpm": 0 * T_C}))
    mat = get_material(MATERIAL)
    b = asm.bearing
    r_fit = 0.5 * asm.shaft.seat_diameter_mm
    closed_form = fit_pressure_MPa(0.0, r_fit, 0.5 * b.inner_ring_outer_diameter_mm,
                                   mat.E_MPa, mat.nu, mat.E_MPa, mat.nu, 0.0)
    one_um = fit_pressure_MPa(0.0, r_fit, 0.5 * b.inner_ring_outer_diameter_mm,
                              mat.E_MPa, mat.nu, mat.E_MPa, mat.nu, 1.0)
    assert closed_form == 0.0 and one_um > 1.0
    for p in (res.fits.inner_MPa, res.fits.outer_MPa):
        np.testing.assert_allclose(p, closed_form, atol=1e-9 * one_um)
    rel = res.pair.preload_N / asm.preload.assembled_N - 1.0
    growth = np.abs(mat.thermal_strain(T_C, asm.T_ref_C))
    assert np.all(np.abs(rel) <= growth + 1e-12)
    # 1 K steps of a smooth function: second differences of the order (alpha dT)^2, not jumps
    assert np.abs(np.diff(rel, 2)).max() < 1e-8
def test_a_one_micrometre_fit_still_closes(line_to_line):
    """The round-off floor does not swallow a real fit: +1 um diametral interference at the
    inner fits (the same unit solutions, states at -80, 20 and 80 C) carries the Lame pressure
    of a solid shaft in the inner ring's effective section to 10 % (the ring is 12 mm long on a
    shaft with a shoulder, not Lame's infinite cylinders: measured +5 %), the outer fit 0."""
    pl = line_to_line
    T = np.array([-80.0, 20.0, 80.0])
    theta, _, w2 = _uniform_states(pl, T)
    delta = pl.fe_stage.deltas_mm(np.ones(3), np.zeros(3))
    p = pl.fe_stage.fit_pressures(pl.sup.evaluate(theta, delta, w2).force_N)
    mat = get_material(MATERIAL)
    lame = fit_pressure_MPa(0.0, 0.5 * pl.asm.shaft.seat_diameter_mm,
                            0.5 * pl.asm.bearing.inner_ring_outer_diameter_mm,
                            mat.E_MPa, mat.nu, mat.E_MPa, mat.nu, 1.0)
    keys = [f.key for f in pl.section.fits]
    inner = p[:, [k == "inner" for k in keys]]
    outer = p[:, [k == "outer" for k in keys]]
    np.testing.assert_allclose(inner, lame, rtol=0.10)
    np.testing.assert_allclose(outer, 0.0, atol=1e-9 * lame)


def test_a_solver_failure_names_the_row_the_fit_and_what_to_try(line_to_line, monkeypatch):
    """A forced failure (an active set that never solves a state, three steps allowed) is the
    package's ValueError subclass, one line, naming the row (1-based, as in the conditions
    table: the first row tried is the 40 C one, row 2), the fits and what to try."""
    import fem.solver as solver

    pl = line_to_line
    pl.sup.clear_cache()
    monkeypatch.setattr(solver, "MAX_ACTIVE_SET_STEPS", 3)
    monkeypatch.setattr(solver.ActiveSet, "satisfied",
                        lambda self, V, *tol: np.zeros(V.shape[0], bool))
    T = np.array([20.0, 40.0])
    with pytest.raises(SolveError) as err:
        pl.run(table_inputs(pl.asm, {"T_ambient_C": T, "speed_rpm": 0 * T}), remember=False)
    msg = str(err.value)
    assert isinstance(err.value, ValueError)
    assert "\n" not in msg
    assert msg.startswith("row "), msg
    assert "inner_interference_um = 0" in msg and "outer_interference_um = 0" in msg
    assert "did not settle in 3 iterations" in msg and "try" in msg
