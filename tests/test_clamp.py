"""The clamp with a force (`[cover]`/`[nut]` clamp = "force"): the clamped face as a unilateral
contact with a preloaded spring in series, through the fits' exact-contact route.

References, independent of the code under test:
(a) a free stack under a clamp: two springs in series and the bolted joint's force split
    (Shigley's Mechanical Engineering Design, ch. 8: joint constant C = k_b / (k_b + k_m);
    VDI 2230 Part 1: F = delta / (compliances in series)), with k = E A / L of a bar under
    uniform axial stress (exact in the FE: quadratic elements hold the linear field, so the
    tolerance is round-off, scaled to the force);
(b) a temperature that uses up the clamp force opens the face, and a fit with free clearance
    then carries nothing, as Lamé says (analytic/lame.py: 0 for a clearance), where the rigid tie
    pulls the stack and presses the fit (0.28 MPa across 2.56 um of clearance);
(c) rigid and compliant are the limits: the FE answer converges to the tied face at order 1 in
    the clamp's compliance, and a clamp without force or stiffness is the untied face exactly.
"""
from __future__ import annotations

import copy
import tomllib

import numpy as np
import pytest

from fem.model import HOLD_RATIO, build_model, face_weights
from fem.solver import FitSolver, Superposition
from meshes.section import Face, Rect, Section, Split
from studies.model.config import CONFIG_DIR, ConfigError, assembly_from_dict

# the free stack: a steel tube on a roller (z = 0), an aluminium cover on it held by a roller on
# its top; the face between them at z = L
R0, R1, L, W = 10.0, 15.0, 20.0, 3.0
AREA = np.pi * (R1 ** 2 - R0 ** 2)
E_S, E_C = 200000.0, 68900.0                     # 9Cr18 and 6061 (analytic/materials.py)


def _section(face: bool = True, tied: bool = False, c_mm_per_N: float = 0.0) -> Section:
    rects = (Rect("stack", R0, R1, 0.0, L, "9Cr18"), Rect("cover", R0, R1, L, L + W, "6061"))
    split = Split("face", "z", L, R0, R1, ("stack",), ("cover",), tied)
    faces = (Face("face", ("stack",), ("cover",), L, R0, R1, "clamp", c_mm_per_N),) if face else ()
    return Section(rects, (split,), (), (0.0, L + W), (), {}, 1.0, 0.5, 0.0, (), faces)


def _k_stack():
    return E_S * AREA / L                         # N/mm, the tube as a bar


def _k_cover():
    return E_C * AREA / W


def _face_force(solver, force_N):
    return force_N[..., solver.face_pair].sum(axis=-1)


def test_face_weights_integrate_a_uniform_pressure_exactly():
    """Their sum is the annulus area, their first moment 2 pi (r1^3 - r0^3) / 3 (Simpson's rule
    is exact for the cubic r^2 on each element)."""
    r = np.linspace(3.0, 8.0, 9)
    w = face_weights(r)
    assert w.sum() == pytest.approx(np.pi * (8.0 ** 2 - 3.0 ** 2), rel=1e-13)
    assert (w * r).sum() == pytest.approx(2 * np.pi * (8.0 ** 3 - 3.0 ** 3) / 3, rel=1e-13)


def test_free_stack_under_a_clamp_is_the_bolted_joint_closed_form():
    """(a) Tightened by an overlap delta, the face carries delta / (1/k_m + 1/k_b + 1/k_cover);
    heating the stack adds its free growth to delta; an external load P pushing the stack off the
    face unloads the face by C P, C = k_clamp / (k_clamp + k_m) (k_clamp: the clamp's spring and
    the cover in series), and the face opens at P = F_i / C. Each to 1e-9 of the force."""
    kb = 2.0e5                                                   # N/mm, the clamp's spring
    solver = FitSolver(build_model(_section(c_mm_per_N=1.0 / kb)))
    m = solver.model
    k_clamp = 1.0 / (1.0 / kb + 1.0 / _k_cover())
    k_series = 1.0 / (1.0 / _k_stack() + 1.0 / k_clamp)
    delta = 2e-3                                                 # mm
    F_i = delta * k_series
    zero = np.zeros(m.ndofs)
    sol = solver.solve(zero, [delta])
    assert _face_force(solver, sol.force_N) == pytest.approx(F_i, rel=1e-9)

    # thermal: the stack heated (strain eps) or cooled past the overlap
    sup = Superposition(solver)
    i = m.part_names.index("stack")
    for eps in (3e-5, -5e-5, -1.5e-4):
        theta = np.zeros((1, len(m.part_names)))
        theta[0, i] = eps
        res = sup.evaluate(theta, np.array([[delta]]))
        expect = max(delta + eps * L, 0.0) * k_series
        assert _face_force(solver, res.force_N[0]) == pytest.approx(expect, rel=1e-9, abs=1e-9 * F_i)
        if expect == 0.0:            # open: every pair apart by the lost overlap
            np.testing.assert_allclose(res.gap_mm[0], -(delta + eps * L), rtol=1e-8)

    # an external axial load on the stack's top face (uniform, towards the base: -z)
    fp = m.fits[0]
    w = face_weights(fp.z_mm)
    C = k_clamp / (k_clamp + _k_stack())
    P0 = F_i / C                                                 # the face opens here

    def face_force_at(P):
        f = np.zeros(m.ndofs)
        f[fp.master_r] -= P * w / w.sum()
        return _face_force(solver, solver.solve(f, [delta]).force_N)

    for P in (0.3 * P0, 0.99 * P0):
        assert face_force_at(P) == pytest.approx(F_i - C * P, rel=1e-9)
    assert face_force_at(1.01 * P0) == pytest.approx(0.0, abs=1e-9 * F_i)


def test_rigid_and_compliant_are_the_limits_of_the_force_clamp():
    """(c) The stack heated by eps: the rise of its top (relative to the tightened state) is the
    bar's eps L - F c_m, F = eps L / (c_m + c + c_cover) (compliances c_m = L / (E_s A) of the
    stack, c of the clamp's spring, c_cover = W / (E_c A)), to 1e-9 of eps L, for the tied face
    (c = 0), the untied one (F = 0: the free growth) and the force clamp with c from 1e-11 to
    1e-1 mm/N; so the force clamp tends to "rigid" as c -> 0 and to "compliant" as c -> inf (no
    overlap), each at order 1 in c (resp. 1 / c): the error falls tenfold per decade to 2 %."""
    eps = 4e-5
    top = np.array([[0.5 * (R0 + R1)], [L - 1e-9]])
    c_m, c_cov = 1.0 / _k_stack(), 1.0 / _k_cover()

    def rise(section, delta):
        solver = FitSolver(build_model(section))
        m = solver.model
        probe = m.probe_matrix(top)
        theta = np.zeros(len(m.part_names))
        theta[m.part_names.index("stack")] = eps
        if section.faces:
            hot = solver.solve(m.unit_loads @ theta, [delta]).u
            cold = solver.solve(np.zeros(m.ndofs), [delta]).u
        else:                        # no contact: one linear solve
            hot = solver.solve_status(np.zeros(0, bool), m.unit_loads @ theta, np.zeros(0))[:, 0]
            cold = np.zeros(m.ndofs)
        return float((probe @ (hot - cold))[1])

    def bar(c):
        return eps * L * (1.0 - c_m / (c_m + c + c_cov))

    tied = rise(_section(face=False, tied=True), 0.0)
    free = rise(_section(face=False, tied=False), 0.0)
    assert tied == pytest.approx(bar(0.0), rel=1e-9)
    assert free == pytest.approx(eps * L, rel=1e-9)
    stiff = [1e-9, 1e-10, 1e-11]
    soft = [1e-3, 1e-2, 1e-1]
    r_stiff = [rise(_section(c_mm_per_N=c), 1e-3) for c in stiff]
    r_soft = [rise(_section(c_mm_per_N=c), 0.0) for c in soft]
    for c, r in zip(stiff + soft, r_stiff + r_soft):
        assert r == pytest.approx(bar(c), abs=1e-9 * eps * L)
    for errs in ([r - tied for r in r_stiff], [free - r for r in r_soft]):
        assert errs[0] / errs[1] == pytest.approx(10.0, rel=0.02)
        assert errs[1] / errs[2] == pytest.approx(10.0, rel=0.02)


# ------------------------------------------------------------------ through the pipeline
def _raw():
    with open(CONFIG_DIR / "seed000_71807C_TC4.toml", "rb") as fh:
        return tomllib.load(fh)


def _sleeved(clamp: str, force_N: float = 0.0) -> dict:
    """Seed 000's pair in a steel sleeve in an aluminium housing and cover (the issue's rig in
    small): the outer rings with 2.56 um of clearance in the sleeve."""
    raw = _raw()
    raw["housing"].update(material="6061", bore_diameter_mm=53.0, outer_diameter_mm=66.0)
    raw["cover"].update(material="6061", clamp=clamp)
    if force_N:
        raw["cover"]["clamp_force_N"] = force_N
    raw["sleeve"] = {"material": "9Cr18", "radial_thickness_mm": 3.0, "length_mm": 24.0}
    raw["fits"].update(outer_interference_um=-2.56, sleeve_interference_um=10.0)
    return raw


def test_a_clamp_force_used_up_opens_the_stack_and_the_fit_returns_to_lame():
    """(b) Heated to 60 C, the aluminium housing outgrows the steel stack: the rigid cover pulls
    the stack and the outer fit carries a pressure across its free clearance (Lamé: 0); a clamp
    of 500 N is used up (force 0, flagged, margin <= 0) and the fit carries nothing. At T_ref the
    clamp carries its force; a row whose axial load exceeds it is flagged with margin F - |Fa|
    (F the least force over the stack's faces)."""
    from studies.model.columns import to_columns
    from studies.model.pipeline import Pipeline, simulate_table

    def run(asm, direct=False):      # on a mesh coarsened 4x: what is asserted is exact on any mesh
        return simulate_table(asm, cond, direct=direct, pipeline=Pipeline.shared(asm, mesh_factor=4.0))

    cond = {"T_ambient_C": np.array([20.0, 60.0, 20.0]), "axial_load_N": np.array([0.0, 0.0, 600.0])}
    rigid = run(assembly_from_dict(_sleeved("rigid"), "rigid.toml"))
    force = run(assembly_from_dict(_sleeved("force", 500.0), "force.toml"))
    for r in (rigid, force):
        assert r.fe.interference_um[1, 1] < 0 and r.lame.fit_pressure_outer_MPa[1] == 0.0
    p_ref = rigid.fits.outer_MPa[0]
    assert rigid.fits.outer_MPa[1] > 0.1 * p_ref                   # the rigid tie's artefact
    assert force.fits.outer_MPa[1] <= 1e-12 * p_ref                # Lamé's 0
    out = to_columns(force)
    np.testing.assert_allclose(out["clamp_force_N"], [500.0, 0.0, 500.0], rtol=1e-9, atol=1e-9 * 500)
    # the stack's faces (studies/model/stack.py STACK_FACES): the housing shoulder under ring A
    # and the sleeve carries the whole clamp force (equilibrium of the stator), the two ring-
    # spacer faces in series carry the rings' share of it, the rest goes through the sleeve
    # beside them; the margin is the least face force less |axial_load_N|
    ff = force.fe.face_force_N        # clamp, shoulder, ring A - spacer, spacer - ring B
    np.testing.assert_allclose(ff[[0, 2], 1], [500.0, 500.0], rtol=1e-9)
    # (to HOLD_RATIO: the ring faces are partly open, dished by the fits, and the weak springs
    # across them carry HOLD_RATIO E A / L times their gap, 1e-8 of the force here)
    np.testing.assert_allclose(ff[[0, 2], 2], ff[[0, 2], 3], rtol=HOLD_RATIO)
    share = ff[0, 1:].min()
    assert 0.0 < share < 500.0
    np.testing.assert_allclose(out["margin_clamp_N"], [share, 0.0, share - 600.0], rtol=1e-9,
                               atol=1e-9 * 500)
    assert out["flag_clamp_open"].tolist() == [0.0, 1.0, 1.0]
    assert "clamp_force_N" not in to_columns(rigid)                # only with a clamp force
    # the superposition against a full FE solve per row (the clamp's spring in the stiffness)
    direct = run(assembly_from_dict(_sleeved("force", 500.0), "force.toml"), direct=True)
    for a, b in ((direct.fe.fit_pressure_MPa, force.fe.fit_pressure_MPa),
                 (direct.fe.face_force_N, force.fe.face_force_N),
                 (direct.fe.dz_mm, force.fe.dz_mm)):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-8 * np.abs(b).max())


def test_a_clamp_without_force_or_stiffness_is_the_compliant_cover():
    """(c) through the whole route: a force clamp of 1e-3 N with a spring of 1e-6 N/um gives
    every output of the compliant cover (seed 000 at -60 and 20 C) to 1e-5 of each column's
    scale (what is left of the clamp is 1e-3 N and 1 N/mm, against a preload of 100 N and a
    stack of about 1e6 N/mm: the force ratio 1e-5). The compliant cover keeps the stack's own
    faces tied; under a force clamp they are contacts (tests/test_stack_faces.py), so at 80 C,
    where the fits dish the ring faces and part of each opens, the two differ (by 2e-3 here:
    the tied faces' tension, the artefact of tied faces). Both on one mesh coarsened 4x: the
    two clamps are compared on the same mesh, and the limit holds on any."""
    from studies.model.columns import to_columns
    from studies.model.pipeline import Pipeline, simulate_table

    def run(asm):
        return to_columns(simulate_table(asm, cond, pipeline=Pipeline.shared(asm, mesh_factor=4.0)))

    cond = {"T_ambient_C": np.array([-60.0, 20.0, 80.0])}
    raw = _raw()
    comp = run(assembly_from_dict(raw, "c.toml"))
    raw = copy.deepcopy(raw)
    raw["cover"].update(clamp="force", clamp_force_N=1e-3, clamp_stiffness_N_per_um=1e-6)
    force = run(assembly_from_dict(raw, "f.toml"))
    worst_hot = 0.0
    for k, v in comp.items():
        scale = max(np.abs(v).max(), 1e-30)
        np.testing.assert_allclose(force[k][:2], v[:2], rtol=0, atol=1e-5 * scale, err_msg=k)
        worst_hot = max(worst_hot, abs(force[k][2] - v[2]) / scale)
    assert worst_hot > 1e-4


@pytest.mark.parametrize("change,expect", [
    ({"clamp": "force"}, 'cover.clamp_force_N: clamp = "force" needs the clamp force'),
    ({"clamp": "rigid", "clamp_force_N": 100.0}, 'cover.clamp_force_N: only used with clamp = "force"'),
    ({"clamp": "compliant", "clamp_stiffness_N_per_um": 100.0},
     'cover.clamp_stiffness_N_per_um: only used with clamp = "force"'),
])
def test_clamp_keys_are_checked(change, expect):
    raw = _raw()
    raw["cover"].update(change)
    with pytest.raises(ConfigError) as e:
        assembly_from_dict(raw, "x.toml")
    assert "\n" not in str(e.value) and expect in str(e.value)
    raw = _raw()
    raw["cover"].update(clamp="force", clamp_force_N=100.0)
    raw["fits"]["contact"] = "bonded"
    with pytest.raises(ConfigError, match='cover.clamp: "force" needs fits.contact = "frictionless"'):
        assembly_from_dict(raw, "x.toml")


def test_design_search_family_holds_the_clamp_spring():
    """The design search's parametric set-up (fem/parametric.py) of a stack with a force clamp
    equals the stack's own full set-up (a second method) to 1e-9 of each array: the clamp's
    spring on the diagonal of the flexibility and the face closed for the preload-path
    compliance."""
    from fem.parametric import Family
    from fem.setup import compute_setup, full_fe
    from studies.model.pipeline import Pipeline
    from studies.usecases.design_search import SPACERS, Stack

    raw = _raw()
    raw["cover"].update(clamp="force", clamp_force_N=2000.0)
    asm = assembly_from_dict(raw, "f.toml")
    L = asm.inner_spacer.length_mm

    def spec(inner, outer):
        stack = Stack(inner, outer, L, asm.nut.clamp, asm.cover.clamp)
        return Pipeline(stack.assembly(asm), mesh_factor=4.0, superpose=False).spec

    fam = Family(spec("TC4", "9Cr18"), SPACERS)
    s = spec("6061", "Si3N4")
    par, own = fam.setup(s), compute_setup(s, full_fe(s))
    assert "face_clamp_cover" in own.fit_names and "face_outer_A_spacer" in own.fit_names
    for name in ("B", "A", "probe_units"):
        a, b = getattr(par.condensed, name), getattr(own.condensed, name)
        assert np.abs(a - b).max() <= 1e-9 * np.abs(b).max(), name
    assert par.compliance_mm_per_N == pytest.approx(own.compliance_mm_per_N, rel=1e-9)


def test_the_shipped_rig_runs_with_its_clamp_force():
    """studies/configs/rig_cartridge_sleeve.toml (the rig): tightened to 3.89 kN at T_ref;
    at +60 C its aluminium housing has outgrown the stack and used the force up (flagged). On a
    mesh coarsened 4x (its set-up on the file's mesh costs ~6 s of CPU): at T_ref the clamp
    carries its tightening force on any mesh (nothing else loads the face yet), and +60 C is far
    past the opening: the force falls to ~430 N at 30 C and to 0 by 40 C on the file's mesh and on
    this one alike (measured: 440 and 420 N at 30 C)."""
    from studies.model.columns import to_columns
    from studies.model.config import load_assembly
    from studies.model.pipeline import Pipeline, simulate_table

    asm = load_assembly(CONFIG_DIR / "rig_cartridge_sleeve.toml")
    assert asm.cover.clamp == "force" and asm.cover.clamp_force_N == 3890.0
    out = to_columns(simulate_table(asm, {"T_ambient_C": np.array([20.0, 60.0])},
                                    pipeline=Pipeline.shared(asm, mesh_factor=4.0)))
    assert out["clamp_force_N"][0] == pytest.approx(3890.0, rel=1e-9)
    assert out["flag_clamp_open"].tolist() == [0.0, 1.0]


@pytest.mark.parametrize("d,P,d2,mu,D_Km", [(100.0, 1.5, 99.026, 0.12, 103.8),
                                             (10.0, 1.25, 9.188, 0.10, 13.5),
                                             (10.0, 1.5, 9.026, 0.0, 13.5),
                                             (24.0, 3.0, 22.051, 0.16, 31.0)])
def test_tightening_force_is_the_power_screw_torque(d, P, d2, mu, D_Km):
    """VDI 2230's tightening torque (step R13, `analytic.clamp.tightening_force_N`) against the
    exact torque of a power screw raising a load (Shigley's Mechanical Engineering Design, 10th
    ed., eq. 8-27: T = F d_m / 2 (l + pi f d_m sec a) / (pi d_m - f l sec a) + F f_c d_c / 2, a =
    30 deg the ISO flank half-angle, l = P, d_m = d_2, the pitch diameters of the ISO 724
    tables): VDI's 0.16 P and 0.58 d_2 are P / (2 pi) and d_2 / (2 cos 30 deg) rounded, so the
    two agree to 1 %."""
    from analytic.clamp import tightening_force_N

    torque = 20000.0
    sec = 1.0 / np.cos(np.radians(30.0))
    per_N = 0.5 * d2 * (P + np.pi * mu * d2 * sec) / (np.pi * d2 - mu * P * sec) + 0.5 * mu * D_Km
    assert tightening_force_N(torque, d, P, mu, mu, D_Km) == pytest.approx(torque / per_N, rel=1e-2)


def test_the_thin_section_rig_runs_with_its_nut_force():
    """studies/configs/rig_thin_section_hub.toml (the second rig): its aluminium shaft
    nut is tightened to the 1497 N of its torque (VDI 2230, in the file's comment) at T_ref; the
    aluminium shaft outgrows the steel inner-ring stack when hot, so the nut's force falls and is
    used up by +70 C (flagged), and rises when cold. Every fit (inner, outer, the hub = sleeve)
    has its pressure and flag columns beside the clamp's."""
    from analytic.clamp import tightening_force_N
    from studies.model.columns import to_columns
    from studies.model.config import load_assembly
    from studies.model.pipeline import simulate_table

    asm = load_assembly(CONFIG_DIR / "rig_thin_section_hub.toml")
    assert asm.nut.clamp == "force"
    assert asm.nut.clamp_force_N == pytest.approx(
        tightening_force_N(20000.0, 100.0, 1.5, 0.12, 0.12, (101.6 + 106.0) / 2), abs=0.5)
    cond = {"T_ambient_C": np.array([-45.0, 20.0, 70.0]), "speed_rpm": np.zeros(3)}   # at rest,
    out = to_columns(simulate_table(asm, cond))        # as the nut was tightened
    f = out["clamp_force_N"]
    assert f[1] == pytest.approx(asm.nut.clamp_force_N, rel=1e-9)
    assert f[0] > f[1] and f[2] == 0.0
    assert out["flag_clamp_open"].tolist() == [0.0, 0.0, 1.0]
    for fit in ("inner", "outer", "sleeve"):
        for col in (f"fit_pressure_{fit}_MPa", f"flag_fit_open_{fit}", f"interference_{fit}_um"):
            assert col in out, col


def test_a_very_soft_clamp_spring_is_warned_about():
    """A clamp spring of 1e-3 N/um on seed 000's cover (its thread gives ~1500 N/um, VDI 2230:
    a ratio of 7e-7, below CLAMP_SOFT_WARN) gets one warning line naming the key and the overlap
    it is tightened by (F / k = 1000 N / 1 N/mm = 1000 mm); a bolted cover's 100 N/um gets none."""
    from studies.model.checks import plausibility_warnings

    for k, n in ((1e-3, 1), (100.0, 0)):
        raw = _raw()
        raw["cover"].update(clamp="force", clamp_force_N=1e3, clamp_stiffness_N_per_um=k)
        msgs = [m for m in plausibility_warnings(assembly_from_dict(raw, "x.toml"))
                if "clamp_stiffness" in m]
        assert len(msgs) == n
        if n:
            assert "\n" not in msgs[0] and "cover.clamp_stiffness_N_per_um = 0.001" in msgs[0]
            assert "tightened by 1e+03 mm" in msgs[0]


def test_design_varies_the_clamp_force_on_one_fe_setup(monkeypatch):
    """`design --vary nut_clamp_force_N=...`: the thin-section rig's nut at its 1497 N
    and at 3000 N are one FE set-up (the set-up route called once: the set-up holds the clamp's
    spring, not its force), and each setting's answers equal those of the assembly built with
    that force through its own pipeline (a second route, its own set-up) to 1e-9 of the preload.
    The stiffer clamp keeps the aluminium shaft's stack closed to a higher temperature: at 40 C
    (above the 1497 N nut's opening, about +35 C) the two preloads differ. A force for a rigid cover
    or a force <= 0: one line."""
    import fem.parametric as fp
    from studies.model.config import load_assembly
    from studies.model.inputs import baseline_inputs
    from studies.model.pipeline import Pipeline
    from studies.usecases import design_search as ds

    asm = load_assembly(CONFIG_DIR / "rig_thin_section_hub.toml")
    settings = ds.settings_of(asm, {"nut_clamp_force_N": (3000.0,)})
    assert [s.nut_clamp_force_N for s in settings] == [1497.0, 3000.0]
    assert settings[1].assembly(asm).nut.clamp_force_N == 3000.0
    assert settings[1].label(settings[0]) == "nut 3000 N"
    calls = []
    real = fp.Family.setup
    monkeypatch.setattr(fp.Family, "setup", lambda self, spec: calls.append(1) or real(self, spec))
    stack = ds.candidates(asm, length_factors=(1.0,), materials=["17-4PH"])[0]
    T, P0 = np.array([20.0, 40.0]), np.array([150.0])
    r = ds.evaluate_settings(asm, stack, tuple(settings), T, P0, 4.0, parametric=True)
    assert len(calls) == 1
    for s, ans in zip(settings, r):
        a = s.assembly(stack.assembly(asm))
        cols = {"T_ambient_C": T, "preload_assembled_N": np.full(2, 150.0)}
        own = Pipeline(a, mesh_factor=4.0).run(
            baseline_inputs(cols, 2, a.T_ref_C, a.preload.assembled_N, a.lubrication.speed_rpm))
        np.testing.assert_allclose(ans.preload_N[0], own.preload_N, rtol=0, atol=1e-9 * 150.0)
    assert abs(r[1].preload_N[0, 1] - r[0].preload_N[0, 1]) > 1.0
    for vary, frag in (({"cover_clamp_force_N": (100.0,)}, "the cover's clamp is 'rigid'"),
                       ({"nut_clamp_force_N": (0.0,)}, "must be > 0")):
        with pytest.raises(ds.DesignError, match=frag):
            ds.settings_of(asm, vary)
