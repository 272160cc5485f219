"""The parametric FE set-up (fem/parametric.py) against the full set-up of the same stack.

The reference is the stack's own FE set-up (`fem.setup.compute_setup`: its own mesh, assembly,
factorisation and unit solutions), a second method: the parametric route never assembles or
factorises the member's stiffness, it condenses the spacers and updates the reference family's
factorisation by the Woodbury identity. The two are the same algebra, so they must agree to
round-off: 1e-9 relative to the largest entry of each array (the round-off of ~1e4 DOF solves
is ~1e-13; the bound leaves room for the conditioning of the update, E ratios up to 20 here).
"""
import numpy as np
import pytest

from analytic.materials import get_material
from fem.parametric import Family, FamilyError, family_key, member_spec
from fem.setup import compute_setup, full_fe
from studies.model.config import load_shipped
from studies.model.pipeline import Pipeline
from studies.usecases.design_search import SPACERS, Stack, evaluate_stack, parametric_setup_of

MESH_FACTOR = 4.0       # the coarse mesh the design tests use
RTOL = 1e-9


def _spec(asm, stack):
    return Pipeline(stack.assembly(asm), mesh_factor=MESH_FACTOR, superpose=False).spec


@pytest.fixture(scope="module")
def family():
    asm = load_shipped("seed000")
    L = asm.inner_spacer.length_mm
    ref = Stack("TC4", "9Cr18", L, asm.nut.clamp, asm.cover.clamp)
    return asm, Family(_spec(asm, ref), SPACERS)


def _rel(a, b):
    return np.abs(a - b).max() / np.abs(b).max()


@pytest.mark.parametrize("inner,outer", [("6061", "Si3N4"), ("9Cr18", "TC4")])
def test_member_setup_equals_its_own_full_setup(family, inner, outer):
    """Spacers of aluminium (E 69 GPa) and silicon nitride (310 GPa) against a TC4 / 9Cr18
    reference, and the two swapped: every array of the condensed contact problem and the
    preload-path compliance equal the stack's own full set-up to round-off."""
    asm, fam = family
    stack = Stack(inner, outer, asm.inner_spacer.length_mm, asm.nut.clamp, asm.cover.clamp)
    spec = _spec(asm, stack)
    par = fam.setup(spec)
    own = compute_setup(spec, full_fe(spec))
    c, d = par.condensed, own.condensed
    assert np.array_equal(c.fit_of_pair, d.fit_of_pair) and par.ndofs == own.ndofs
    for name in ("B", "A", "probe_units"):
        assert _rel(getattr(c, name), getattr(d, name)) < RTOL, name
    assert abs(par.compliance_mm_per_N / own.compliance_mm_per_N - 1) < RTOL
    # the update is not empty: the member's arrays differ from the reference's well beyond RTOL
    ref = fam.setup(fam.spec)
    assert _rel(ref.condensed.B, d.B) > 1e3 * RTOL


def test_other_length_or_clamp_is_another_family(family):
    """A spacer length or a clamp scheme changes the mesh: not a member (FamilyError)."""
    asm, fam = family
    L = asm.inner_spacer.length_mm
    longer = _spec(asm, Stack("TC4", "9Cr18", 2 * L, asm.nut.clamp, asm.cover.clamp))
    other_clamp = _spec(asm, Stack("TC4", "9Cr18", L, asm.nut.clamp,
                                   "rigid" if asm.cover.clamp != "rigid" else "compliant"))
    for spec in (longer, other_clamp):
        assert family_key(spec, SPACERS) != fam.key
        with pytest.raises(FamilyError):
            fam.setup(spec)
    # the materials of a part that is not variable change the family too
    shaft = member_spec(fam.spec, {"shaft": get_material("6061")})
    assert family_key(shaft, SPACERS) != fam.key


def test_design_screening_equals_full_route(family):
    """One task of the design search (preload, contact pressure, fit pressures and torque over
    temperature and preload) through the parametric set-up and through the stack's own: the
    preload range the ranking uses agrees to 1e-9 relative."""
    asm, _ = family
    stack = Stack("6061", "17-4PH", asm.inner_spacer.length_mm, asm.nut.clamp, asm.cover.clamp)
    T = np.array([-60.0, 20.0, 80.0])
    P0 = np.array([0.5, 1.0]) * asm.preload.assembled_N
    par = evaluate_stack(asm, stack, T, P0, MESH_FACTOR, parametric=True)
    own = evaluate_stack(asm, stack, T, P0, MESH_FACTOR, parametric=False)
    for k in ("preload_N", "max_contact_pressure_MPa", "fit_pressure_inner_MPa",
              "fit_pressure_outer_MPa", "torque_Nmm"):
        assert _rel(getattr(par, k), getattr(own, k)) < RTOL, k
    rng = lambda r: np.ptp(r.preload_N, axis=1)      # noqa: E731
    assert np.all(np.abs(rng(par) - rng(own)) < RTOL * rng(own))
    assert parametric_setup_of(asm).keywords["variable"] == SPACERS


def test_screening_on_workers_equals_this_process(family):
    """The family's reference is fixed (the assembly's spacer materials), not the first stack a
    worker happens to see: the screening on 2 Dask workers gives this process's numbers bit for
    bit, whatever stacks each worker gets."""
    from studies.model.parallel import map_blocks

    asm, _ = family
    L = asm.inner_spacer.length_mm
    stacks = [Stack(i, o, L, asm.nut.clamp, asm.cover.clamp)
              for i, o in (("6061", "TC4"), ("Si3N4", "6061"), ("9Cr18", "Si3N4"))]
    T, P0 = np.array([-60.0, 80.0]), np.array([asm.preload.assembled_N])
    blocks = [(asm, s, T, P0, MESH_FACTOR, True) for s in stacks]
    import fem.parametric
    fem.parametric._FAMILIES.clear()    # neither the workers nor this process start with a family
    there = map_blocks(evaluate_stack, blocks, workers=2)
    here = map_blocks(evaluate_stack, blocks[::-1])[::-1]       # another order than the workers'
    for a, b in zip(here, there):
        for k in ("preload_N", "fit_pressure_inner_MPa", "torque_Nmm"):
            np.testing.assert_array_equal(getattr(a, k), getattr(b, k), err_msg=k)


def test_fit_class_stays_in_the_family_and_its_compliance_is_the_full_setups(family):
    """Fit classes change only the assembled interferences the preload-path compliance is taken
    at: k5 on the shaft (the mean inner fit +7.5 um) and P6 in the housing (ISO 286, 30..50 mm:
    -37..-21 um, the outer fit from -1.5 um clearance to +27.5 um interference: its status at
    assembly changes). Each is the same family (no new reference FE), and its compliance equals
    the full set-up's of its own spec to round-off (RTOL); P6's differs from the given fits'."""
    from dataclasses import replace

    asm, fam = family
    stack = Stack("6061", "Si3N4", asm.inner_spacer.length_mm, asm.nut.clamp, asm.cover.clamp)
    given = fam.setup(_spec(asm, stack)).compliance_mm_per_N
    for cls in ({"inner_shaft_class": "k5"}, {"outer_housing_class": "P6"}):
        spec = _spec(replace(asm, fits=replace(asm.fits, **cls)), stack)
        assert spec.compliance != _spec(asm, stack).compliance
        assert family_key(spec, SPACERS) == fam.key
        par = fam.setup(spec)
        own = compute_setup(spec, full_fe(spec))
        assert abs(par.compliance_mm_per_N / own.compliance_mm_per_N - 1) < RTOL
    assert abs(par.compliance_mm_per_N / given - 1) > 1e3 * RTOL
