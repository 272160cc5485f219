"""The stack's own axial faces (ring-shoulder, ring-spacer) as unilateral contacts under a clamp
with a force: they open when the clamp force is exceeded.

A free column of tubes of one cross-section (base on a roller at z = 0, ring, spacer, a cover held
by a roller on its top), each face between them a contact that slides radially, the face under the
cover the clamp's (a spring of compliance C_B in series, tightened by an overlap DELTA). Each tube
is then a bar under uniform axial stress, so k = E A / L is exact in the FE (quadratic elements
hold the linear field) and the references are the closed forms of bars in series:
(a) all faces closed: the same answer as the tied stack (the model before this change), to
    round-off relative to the clamp force; the force through every face delta / sum(1/k);
(b) an external load P at an intermediate plane (the bolted joint with the load introduced inside
    the clamped parts: VDI 2230 Part 1 (2015), the load introduction factor n; Shigley's
    Mechanical Engineering Design, 10th ed., ch. 8): below the plane the faces carry
    F_i - P k_1 / (k_1 + k_2), above it F_i + P k_2 / (k_1 + k_2) (k_1, k_2 the parts below and
    above in series); the faces below open at P = F_i (k_1 + k_2) / k_1 and those above never
    (the predicted order; reversed for a load the other way, where the clamp face opens first);
(c) a spacer cooled past the overlap: the clamp face opens, the stack's faces stay closed at
    zero force;
(d) a part whose faces both open (the ring, when the spacer above it is lifted off it) is held by
    the weak springs of its faces (`fem.model.HOLD_RATIO`): its two gaps split as the springs'
    flexibilities, and what they carry is HOLD_RATIO-small;
(e) parallel paths (a ring column beside a sleeve column between rigid plates): the clamp force
    splits by their stiffness, and a sleeve that outgrows the rings opens the ring column first.
"""
from __future__ import annotations

import numpy as np
import pytest

from analytic.materials import get_material
from fem.model import HOLD_E_MPA, HOLD_RATIO, build_model, face_weights
from fem.solver import FitSolver, Superposition
from meshes.section import Face, Rect, Section, Split

R0, R1 = 10.0, 15.0
AREA = np.pi * (R1 ** 2 - R0 ** 2)
#: (part, material, length mm) bottom to top
PARTS = (("base", "9Cr18", 12.0), ("ring", "TC4", 8.0), ("spacer", "6061", 6.0),
         ("cover", "17-4PH", 3.0))
C_B = 1.0 / 2.0e5                      # mm/N, the clamp's spring
DELTA = 2e-3                           # mm, the overlap the clamp is tightened with


def _z():
    z = np.cumsum([0.0] + [L for _, _, L in PARTS])
    return {p: (z[i], z[i + 1]) for i, (p, _, _) in enumerate(PARTS)}


def _section(contacts: bool = True) -> Section:
    """The column; `contacts=False`: the stack's faces tied (the clamp face a contact always)."""
    z = _z()
    rects = tuple(Rect(p, R0, R1, *z[p], mat) for p, mat, _ in PARTS)
    names = [p for p, _, _ in PARTS]
    splits, faces = [], []
    for lo, hi in zip(names[:-1], names[1:]):
        at = z[lo][1]
        clamp = hi == "cover"
        splits.append(Split(f"face_{lo}_{hi}", "z", at, R0, R1, (lo,), (hi,),
                            tied=not (clamp or contacts)))
        if clamp:
            faces.append(Face(f"face_{lo}_{hi}", (lo,), (hi,), at, R0, R1, "clamp", C_B))
        elif contacts:
            faces.append(Face(f"face_{lo}_{hi}", (lo,), (hi,), at, R0, R1, "stack", 0.0, HOLD_RATIO))
    faces.sort(key=lambda f: f.key != "clamp")          # the clamp face first (delta column 0)
    return Section(rects, tuple(splits), (), (0.0, z["cover"][1]), (), {}, 1.0, 0.5, 0.0, (),
                   tuple(faces))


def _k(part: str) -> float:
    """E A / L of a part (N/mm)."""
    mat, L = next((m, L) for p, m, L in PARTS if p == part)
    return get_material(mat).E_MPa * AREA / L


def _k_hold(part: str) -> float:
    """The weak spring that holds `part` (N/mm): HOLD_RATIO HOLD_E_MPA A / L."""
    L = next(L for p, _, L in PARTS if p == part)
    return HOLD_RATIO * HOLD_E_MPA * AREA / L


def _series(*k: float) -> float:
    return 1.0 / sum(1.0 / v for v in k)


K_B = 1.0 / C_B


@pytest.fixture(scope="module")
def column():
    solver = FitSolver(build_model(_section()))
    return solver, Superposition(solver)


def _deltas(solver) -> np.ndarray:
    """The interference of each face: DELTA on the clamp's, 0 on the stack's."""
    return np.array([DELTA if f.key == "clamp" else 0.0 for f in solver.model.section.faces])


def _face_forces(solver, force_N) -> dict[str, float]:
    return {f.name: float(force_N[solver.fit_of_pair == k].sum())
            for k, f in enumerate(solver.model.section.faces)}


def _load_on(solver, face: str, P: float) -> np.ndarray:
    """A uniform axial traction of resultant P (N, +z) on the -z side of `face` (the top of the
    part below it)."""
    k = [f.name for f in solver.model.section.faces].index(face)
    fp = solver.model.fits[k]
    f = np.zeros(solver.model.ndofs)
    w = face_weights(fp.z_mm)
    f[fp.master_r] += P * w / w.sum()
    return f


def _spring_gap(solver, sol, face: str) -> tuple[float, float]:
    """(k, gap) of the weak spring across `face`: its stiffness (N/mm) and the gap (mm) of its
    node pair in `sol`."""
    m = solver.model
    k = [f.name for f in m.section.faces].index(face)
    pairs = np.flatnonzero(solver.fit_of_pair == k)
    j = int(np.flatnonzero(np.isin(m.hold.slave, solver.slave[pairs]))[0])
    p = pairs[np.flatnonzero(solver.slave[pairs] == m.hold.slave[j])[0]]
    return float(m.hold.k_N_per_mm[j]), float(sol.gap_mm[p])


def test_the_weak_springs_hold_only_the_parts_held_by_faces(column):
    """One spring per stack face (the part above it), of HOLD_RATIO HOLD_E_MPA A / L; the
    model adds no axial support to ring and spacer (they are held by the springs, not fixed)."""
    solver, _ = column
    m = solver.model
    np.testing.assert_allclose(np.sort(m.hold.k_N_per_mm),
                               np.sort([_k_hold("ring"), _k_hold("spacer")]),
                               rtol=1e-12)
    z_fixed = m.dirichlet[m.dirichlet % 2 == 1] // 2
    zs = m.sbasis.doflocs[1, z_fixed]
    top = _z()["cover"][1]
    assert np.all((np.abs(zs) < 1e-9) | (np.abs(zs - top) < 1e-9))      # only the two rollers


def test_all_faces_closed_is_the_tied_stack(column):
    """(a) The tightened column, heated part by part, against the same column with its stack
    faces tied: every face force and the displacement of every node to round-off (1e-9 of the
    clamp force, 1e-9 of the largest displacement); the force is the series closed form."""
    solver, sup = column
    tied = FitSolver(build_model(_section(contacts=False)))
    m, mt = solver.model, tied.model
    F_i = DELTA * _series(*(_k(p) for p, _, _ in PARTS), K_B)
    for part, eps in (("ring", 0.0), ("spacer", 4e-5), ("base", -3e-5)):
        theta = np.zeros(len(m.part_names))
        theta[m.part_names.index(part)] = eps
        sol = solver.solve(m.unit_loads @ theta, _deltas(solver))
        ref = tied.solve(mt.unit_loads @ theta, [DELTA])
        assert sol.closed.all()
        L = next(L for p, _, L in PARTS if p == part)
        expect = (DELTA + eps * L) * _series(*(_k(p) for p, _, _ in PARTS), K_B)
        forces = _face_forces(solver, sol.force_N)
        for name, v in forces.items():
            assert v == pytest.approx(expect, abs=1e-9 * F_i), name
        assert ref.force_N.sum() == pytest.approx(expect, abs=1e-9 * F_i)
        pts = m.sbasis.doflocs
        probe_t = mt.probe_matrix(pts)      # the tied model at the contact model's nodes
        u_t = (probe_t @ ref.u).reshape(-1, 2)
        # a node on an untied face sits in two parts: compare away from the faces
        z_faces = [f.z_mm for f in m.section.faces]
        away = np.min(np.abs(pts[1][:, None] - np.array(z_faces)[None, :]), axis=1) > 1e-6
        u_c = np.column_stack([sol.u[0::2], sol.u[1::2]])
        scale = np.abs(u_t).max()
        np.testing.assert_allclose(u_c[away], u_t[away], rtol=0, atol=1e-9 * scale)
        # the superposition gives the same
        res = sup.evaluate(theta[None, :], _deltas(solver)[None, :])
        for name, v in _face_forces(solver, res.force_N[0]).items():
            assert v == pytest.approx(expect, abs=1e-9 * F_i), name


def test_a_load_inside_the_stack_opens_the_faces_on_its_side(column):
    """(b) P upwards on the ring's top: the faces below (base-ring) carry F_i - P k_1 / (k_1 +
    k_2) with k_1 = base and ring in series, k_2 = spacer, cover and clamp spring in series, and
    open at P_1 = F_i (k_1 + k_2) / k_1; the faces above carry F_i + P k_2 / (k_1 + k_2) and,
    once the faces below are open, P itself (the clamp takes the whole load). P downwards on the
    spacer's top: the clamp face opens first, at P_2 = F_i (k_1' + k_2') / k_2'. Each to 1e-8 of
    the clamp force; beyond the opening the weak spring across the open face carries k_w g (the
    ring's equilibrium, to 1e-8), 2 k_w / k_2 of P at most."""
    solver, _ = column
    F_i = DELTA * _series(*(_k(p) for p, _, _ in PARTS), K_B)
    d = _deltas(solver)
    k1, k2 = _series(_k("base"), _k("ring")), _series(_k("spacer"), _k("cover"), K_B)
    P1 = F_i * (k1 + k2) / k1
    for P in (0.5 * P1, 0.99 * P1):
        f = _face_forces(solver, solver.solve(_load_on(solver, "face_ring_spacer", P), d).force_N)
        assert f["face_base_ring"] == pytest.approx(F_i - P * k1 / (k1 + k2), abs=1e-8 * F_i)
        for name in ("face_ring_spacer", "face_spacer_cover"):
            assert f[name] == pytest.approx(F_i + P * k2 / (k1 + k2), abs=1e-8 * F_i)
    sol = solver.solve(_load_on(solver, "face_ring_spacer", 1.5 * P1), d)
    f = _face_forces(solver, sol.force_N)
    assert f["face_base_ring"] == 0.0
    # the ring's equilibrium: P less the weak spring across the open face below it, k_w g
    # (k_w g / P <= HOLD_RATIO k_ring / k_2: the spring's share, 3e-5 here)
    k_w, g = _spring_gap(solver, sol, "face_base_ring")
    assert g > 0
    for name in ("face_ring_spacer", "face_spacer_cover"):
        assert f[name] == pytest.approx(1.5 * P1 - k_w * g, abs=1e-8 * F_i), name
        assert f[name] == pytest.approx(1.5 * P1, rel=2 * _k_hold("ring") / k2)
    # downwards on the spacer's top: the parts below the plane are base, ring, spacer
    k1d, k2d = _series(_k("base"), _k("ring"), _k("spacer")), _series(_k("cover"), K_B)
    P2 = F_i * (k1d + k2d) / k2d
    for P, opened in ((0.99 * P2, False), (1.01 * P2, True)):
        f = _face_forces(solver, solver.solve(_load_on(solver, "face_spacer_cover", -P), d).force_N)
        expect_clamp = max(F_i - P * k2d / (k1d + k2d), 0.0)
        assert f["face_spacer_cover"] == pytest.approx(expect_clamp, abs=1e-8 * F_i)
        assert (f["face_spacer_cover"] == 0.0) == opened
        for name in ("face_base_ring", "face_ring_spacer"):
            expect = F_i + P * k1d / (k1d + k2d) if not opened else P
            assert f[name] == pytest.approx(expect, abs=1e-8 * F_i), name


def test_a_cooled_spacer_opens_the_clamp_face_and_the_stack_stays_stacked(column):
    """(c) The spacer cooled by eps: the force through every face is (DELTA + eps L_s) over the
    series compliance while positive; past it the clamp face opens by -(DELTA + eps L_s) (to 1e-8
    relative) and the stack's faces stay closed at zero force (the weak springs keep the parts on
    the base: their gaps under 1e-9 of the opening)."""
    solver, sup = column
    m = solver.model
    k_all = _series(*(_k(p) for p, _, _ in PARTS), K_B)
    L_s = next(L for p, _, L in PARTS if p == "spacer")
    i = m.part_names.index("spacer")
    for eps in (-1e-4, -5e-4):
        theta = np.zeros((1, len(m.part_names)))
        theta[0, i] = eps
        res = sup.evaluate(theta, _deltas(solver)[None, :])
        f = _face_forces(solver, res.force_N[0])
        expect = max(DELTA + eps * L_s, 0.0) * k_all
        for name, v in f.items():
            assert v == pytest.approx(expect, abs=1e-9 * DELTA * k_all), name
        if expect == 0.0:
            opening = -(DELTA + eps * L_s)
            for k, face in enumerate(m.section.faces):
                g = res.gap_mm[0, solver.fit_of_pair == k]
                if face.key == "clamp":
                    np.testing.assert_allclose(g, opening, rtol=1e-8)
                else:
                    assert np.abs(g).max() <= 1e-9 * opening, face.name


def test_a_part_whose_faces_all_open_is_held_by_its_weak_springs(column):
    """(d) The spacer pushed up into the cover by P beyond P_1 of (b) with its load on the
    spacer's own top: base-ring and ring-spacer both open, the ring between them carries nothing
    and is placed by its two weak springs, k_r = HOLD_RATIO HOLD_E_MPA A / L_r below it and k_s
    = HOLD_RATIO HOLD_E_MPA A / L_s above: gap_below k_r = gap_above k_s (to 1e-6), the gaps
    adding up to the spacer's lift F (1/k_cover + 1/k_clamp) - DELTA, F = P - k_s gap_above the
    clamp face's force (the spacer's equilibrium), HOLD_RATIO-close to P."""
    solver, _ = column
    m = solver.model
    d = _deltas(solver)
    F_i = DELTA * _series(*(_k(p) for p, _, _ in PARTS), K_B)
    P = 3.0 * F_i
    sol = solver.solve(_load_on(solver, "face_spacer_cover", P), d)
    names = [f.name for f in m.section.faces]
    f = _face_forces(solver, sol.force_N)
    gap = {n: sol.gap_mm[solver.fit_of_pair == k] for k, n in enumerate(names)}
    g_below, g_above = gap["face_base_ring"], gap["face_ring_spacer"]
    assert f["face_base_ring"] == 0.0 and f["face_ring_spacer"] == 0.0
    assert g_below.min() > 0 and g_above.min() > 0           # both faces of the ring open
    kr, gb = _spring_gap(solver, sol, "face_base_ring")
    ks, ga = _spring_gap(solver, sol, "face_ring_spacer")
    assert kr == pytest.approx(_k_hold("ring"), rel=1e-12)
    assert ks == pytest.approx(_k_hold("spacer"), rel=1e-12)
    # the ring unloaded but for its two springs in series: equal forces, a ring moved as a body
    # (its gaps uniform over the face to 10 HOLD_RATIO: the springs' own point loads,
    # HOLD_RATIO-small, deform it locally)
    assert gb * kr == pytest.approx(ga * ks, rel=1e-6)
    np.testing.assert_allclose(g_below, gb, rtol=10 * HOLD_RATIO)
    np.testing.assert_allclose(g_above, ga, rtol=10 * HOLD_RATIO)
    # the spacer: P less its spring's pull into the clamp face; cover and clamp spring
    # compressed by that force lift the spacer by the sum of the ring's gaps (+ DELTA)
    F_c = f["face_spacer_cover"]
    assert F_c == pytest.approx(P - ks * ga, abs=1e-8 * F_i)
    assert F_c == pytest.approx(P, rel=2 * _k_hold("spacer") / _series(_k("cover"), K_B))
    # (mean gaps; to 10 HOLD_RATIO, the springs' local deformation as above)
    assert g_below.mean() + g_above.mean() == pytest.approx(
        F_c * (1.0 / _k("cover") + C_B) - DELTA, rel=10 * HOLD_RATIO)


# ------------------------------------------------------------------ parallel paths
#: two columns side by side between a base and a plate (a ring stack and a sleeve beside it,
#: 1 mm apart radially, each with its own faces), base and plate of a modulus 1e8 x steel (rigid
#: with their bending to about 1e-6), the clamp's spring and a nut above the plate on a roller;
#: the plate is held by a weak spring on the sleeve's face only (which stays closed)
PR0, PR1, PR1G, PR2 = 10.0, 12.0, 13.0, 20.0
PL, PW, NW = 10.0, 2.0, 3.0              # column length, plate and nut width (mm)


def _rigid(name: str):
    from analytic.materials import Material

    return Material(name, 2.0e13, 0.3, 0.0, 7800.0, 50.0, 460.0)


def _parallel_section() -> Section:
    zc, zp, zn = 2.0, 2.0 + PL, 2.0 + PL + PW
    rects = (Rect("base", PR0, PR2, 0.0, zc, "9Cr18"),
             Rect("ring", PR0, PR1, zc, zp, "9Cr18"),
             Rect("sleeve", PR1G, PR2, zc, zp, "6061"),
             Rect("plate", PR0, PR2, zp, zn, "9Cr18"),
             Rect("nut", PR0, PR2, zn, zn + NW, "17-4PH"))
    cols = ("ring", "sleeve")
    splits = (Split("face_base", "z", zc, PR0, PR2, ("base",), cols, False),
              Split("face_plate", "z", zp, PR0, PR2, cols, ("plate",), False),
              Split("face_clamp", "z", zn, PR0, PR2, ("plate",), ("nut",), False))
    faces = (Face("face_clamp", ("plate",), ("nut",), zn, PR0, PR2, "clamp", C_B),
             Face("face_base_ring", ("base",), ("ring",), zc, PR0, PR1, "stack", 0.0, HOLD_RATIO),
             Face("face_base_sleeve", ("base",), ("sleeve",), zc, PR1G, PR2, "stack", 0.0,
                  HOLD_RATIO),
             Face("face_ring_plate", ("ring",), ("plate",), zp, PR0, PR1, "stack", 0.0, 0.0),
             Face("face_sleeve_plate", ("sleeve",), ("plate",), zp, PR1G, PR2, "stack", 0.0,
                  HOLD_RATIO))
    return Section(rects, splits, (), (0.0, zn + NW), (), {}, 1.0, 0.5, 0.0, (), faces)


def test_parallel_paths_split_the_clamp_force_and_the_ring_opens_first():
    """The sleeve column (6061) beside the ring column (steel), the sleeve heated by a free growth
    e: while both are closed the plate (rigid) moves up by u = (k_s e - k_c DELTA) / (k_r + k_s
    + k_c) (k = E A / PL of each column, k_c the clamp's spring and the nut in series), the ring
    column carries -k_r u, the sleeve k_s (e - u) and the clamp their sum (the bolted joint's
    parallel members share by stiffness: VDI 2230 Part 1; Shigley ch. 8); the ring's share falls
    as the sleeve grows, and it opens first, where u = 0 (e = k_c DELTA / k_s); beyond, the sleeve
    alone carries (e + DELTA) k_s k_c / (k_s + k_c). Each face force to 1e-5 of the clamp force
    (measured 1.4e-6: the rigid parts' bending)."""
    mats = {"base": _rigid("rigid"), "plate": _rigid("rigid")}
    solver = FitSolver(build_model(_parallel_section(), materials=mats))
    m = solver.model
    k_r = get_material("9Cr18").E_MPa * np.pi * (PR1 ** 2 - PR0 ** 2) / PL
    k_s = get_material("6061").E_MPa * np.pi * (PR2 ** 2 - PR1G ** 2) / PL
    k_n = get_material("17-4PH").E_MPa * np.pi * (PR2 ** 2 - PR0 ** 2) / NW
    k_c = _series(1.0 / C_B, k_n)
    d = np.array([DELTA if f.key == "clamp" else 0.0 for f in m.section.faces])
    i_s = m.part_names.index("sleeve")
    F0 = DELTA * k_c * (k_r + k_s) / (k_r + k_s + k_c)
    e_open = k_c * DELTA / k_s
    for frac in (0.0, 0.5, 0.95, 1.05, 2.0):
        e = frac * e_open
        theta = np.zeros(len(m.part_names))
        theta[i_s] = e / PL
        f = _face_forces(solver, solver.solve(m.unit_loads @ theta, d).force_N)
        u = (k_s * e - k_c * DELTA) / (k_r + k_s + k_c)
        if u < 0:                                              # both columns closed
            ring, sleeve = -k_r * u, k_s * (e - u)
        else:                                                  # the ring column open
            ring, sleeve = 0.0, k_s * k_c / (k_s + k_c) * (e + DELTA)
        for name, v in (("face_base_ring", ring), ("face_ring_plate", ring),
                        ("face_base_sleeve", sleeve), ("face_sleeve_plate", sleeve),
                        ("face_clamp", ring + sleeve)):
            assert f[name] == pytest.approx(v, abs=1e-5 * F0), (frac, name)
        assert (f["face_ring_plate"] == 0.0) == (frac > 1.0)
