"""Grooved ring sections (studies/model/stack.py, meshes/build.py) and the groove-centre shift
from the displaced groove (fem/post.circle_centre_weights).

Independent references: exact kinematics (a rigid translation moves the fitted centre by that
translation; a uniform thermal strain theta of a free body is u = theta (x - x_fixed), which P2
elements represent exactly, so the centre moves by theta (X_c - x_fixed), i.e. alpha dT r_c
radially); the area of a circular segment for the meshed section; the bearing geometry of Harris
& Kotzalas Vol. 1 ch. 2 (contact points on the ball surface); the direct FE solve for the
superposed groove shifts."""
import dataclasses

import numpy as np
import pytest
from skfem import condense, solve

from analytic.bearing.geometry import SIGNS, BearingGeometry
from analytic.bearing.land import groove_centre_rz_mm, groove_point_rz_mm, land_diameters_mm
from analytic.materials import get_material
from fem.fields import ball_outline_rz_mm
from fem.model import build_model
from fem.post import circle_centre_weights
from meshes.build import section_mesh
from meshes.section import Section
from studies.model.config import ConfigError, assembly_from_dict, load_shipped
from studies.model.stack import ball_centres_rz_mm, grooves_of, section_from_assembly


def grooved(name):
    a = load_shipped(name)
    return dataclasses.replace(a, mesh=dataclasses.replace(a.mesh, ring_section="grooved"))


def _ring_section(asm, ring="inner_ring_A", size=0.5):
    """One grooved ring of `asm`, free (no fits, no neighbours)."""
    full = section_from_assembly(asm)
    g = full.groove_of(ring)
    rect = next(r for r in full.rects if r.part == ring)
    return Section((rect,), raceway_points={ring: g.points_rz_mm[0]}, size_mm=size,
                   fit_size_mm=size / 4, grooves=(g,)), g


def test_groove_points_lie_on_the_ball_at_the_free_contact_angle():
    """The groove point at phi = alpha0 is the contact point: Dw/2 from the ball centre, on the
    line through the ball centre at alpha0 (both rings, both arrangement signs)."""
    g = BearingGeometry.from_spec(load_shipped("seed001").bearing)
    zb = 10.0
    for s in (1.0, -1.0):
        for side in ("inner", "outer"):
            p = groove_point_rz_mm(g, side, zb, s, g.alpha0_deg)[:, 0]
            d = p - np.array([g.dm_mm / 2, zb])
            assert np.hypot(*d) == pytest.approx(g.Dw_mm / 2, rel=1e-12)
            a = np.radians(g.alpha0_deg)
            k = -1.0 if side == "inner" else 1.0
            assert d == pytest.approx(k * g.Dw_mm / 2 * np.array([np.cos(a), s * np.sin(a)]), abs=1e-12)
            rc, zc = groove_centre_rz_mm(g, side, zb, s)
            f = g.f_i if side == "inner" else g.f_o
            assert np.hypot(p[0] - rc, p[1] - zc) == pytest.approx(f * g.Dw_mm, rel=1e-12)


def test_circle_fit_weights_exact_for_translation_and_dilation():
    c = np.array([20.0, 3.0])
    phi = np.radians(np.linspace(-15, 45, 13))
    X = c[:, None] + 2.0 * np.array([-np.cos(phi), np.sin(phi)])
    t = np.array([1.3e-3, -0.7e-3])
    theta = 1.7e-3
    for free in (False, True):
        W, w = circle_centre_weights(X, c, free_radius=free)
        assert W @ np.tile(t, X.shape[1]) == pytest.approx(t, abs=1e-15)
        assert W @ (theta * X).T.ravel() + theta * w == pytest.approx(theta * c, rel=1e-12)


def test_held_radius_fit_reads_a_radius_change_as_the_surface_motion():
    """An elastic change dR of the groove radius about a fixed centre (u = dR n on every point):
    the free fit returns the centre unmoved (the radius took it); the fit with the radius held
    at its thermal growth (theta = 0 here) moves the centre so that the model's circle passes
    through the displaced surface in the least-squares sense: dc = dR pinv(n^T) 1, the closed form
    of min_dc sum (dR - n_i . dc)^2, and for an arc symmetric about direction e, dc = dR (sum n_i .
    e / sum (n_i . e)^2) e."""
    c = np.array([20.0, 3.0])
    phi = np.radians(np.linspace(-30, 30, 13))
    e = np.array([np.cos(np.radians(15.0)), np.sin(np.radians(15.0))])
    ang = np.arctan2(e[1], e[0]) + phi
    n = np.array([np.cos(ang), np.sin(ang)])
    X = c[:, None] + 2.0 * n
    dR = 1e-4
    u = (dR * n).T.ravel()
    W_free, _ = circle_centre_weights(X, c, free_radius=True)
    assert W_free @ u == pytest.approx(np.zeros(2), abs=1e-16)
    W, _ = circle_centre_weights(X, c)
    ne = n.T @ e
    assert W @ u == pytest.approx(dR * ne.sum() / (ne ** 2).sum() * e, rel=1e-10)


def test_meshed_section_area_is_rectangles_minus_groove_segments():
    """Area of the triangles = sum of rectangles - the circular segments the grooves cut, up to
    the chord error of the polygonal arc (segment of each boundary edge h: h^3 / (12 R))."""
    sec = section_from_assembly(grooved("seed000"))
    m = section_mesh(sec)
    p, t = m.points, m.triangles
    area = 0.5 * np.abs((p[0, t[1]] - p[0, t[0]]) * (p[1, t[2]] - p[1, t[0]])
                        - (p[0, t[2]] - p[0, t[0]]) * (p[1, t[1]] - p[1, t[0]])).sum()
    expected, chord = sum((r.r1_mm - r.r0_mm) * (r.z1_mm - r.z0_mm) for r in sec.rects), 0.0
    for g in sec.grooves:
        rect = next(r for r in sec.rects if r.part == g.part)
        d = min(abs(g.r_mm - rect.r1_mm), abs(g.r_mm - rect.r0_mm))   # chord at the land
        R = g.radius_mm
        expected -= R ** 2 * np.arccos(d / R) - d * np.sqrt(R ** 2 - d ** 2)
        on = np.abs(np.hypot(p[0] - g.r_mm, p[1] - g.z_mm) - R) < 1e-7 * R
        e = np.concatenate([t[[0, 1]], t[[1, 2]], t[[2, 0]]], axis=1)
        arc = np.unique(np.sort(e[:, on[e[0]] & on[e[1]]], axis=0), axis=1)
        h = np.hypot(*(p[:, arc[0]] - p[:, arc[1]]))
        chord += (h ** 3 / (12 * R)).sum()
        assert arc.shape[1] >= 5                       # the arc is resolved by several edges
    assert chord < 1e-3 * expected
    assert abs(area - expected) <= 1.05 * chord + 1e-9 * expected


def test_rigid_translation_moves_fitted_centre_by_that_translation():
    sec, g = _ring_section(grooved("seed000"))
    model = build_model(sec)
    t = np.array([2.0e-3, -1.0e-3])
    u = np.tile(t, model.ndofs // 2)                  # interleaved (u_r, u_z) per node
    W, _ = circle_centre_weights(np.array(g.points_rz_mm).T, (g.r_mm, g.z_mm))
    probe = model.probe_matrix(np.array(g.points_rz_mm).T)
    assert W @ (probe @ u) == pytest.approx(t, rel=1e-10)


@pytest.mark.parametrize("ring", ["inner_ring_A", "outer_ring_B"])
def test_uniform_thermal_expansion_of_free_ring_moves_centre_by_alpha_dT_rc(ring):
    """Free grooved ring heated by dT: u = theta (x - x_fixed) with theta = alpha dT (u_r = 0 on
    no axis here: the ring is free radially; one u_z is held at its lowest node). The fitted
    groove centre moves by theta r_c radially and theta (z_c - z_fixed) axially."""
    asm = grooved("seed000")
    sec, g = _ring_section(asm, ring)
    model = build_model(sec)
    theta = get_material(asm.bearing.ring_material).thermal_strain(100.0, 20.0)
    f = model.unit_loads @ np.array([theta])
    u = solve(*condense(model.K, f, D=model.dirichlet))
    z_fixed = model.sbasis.doflocs[1, model.dirichlet[0] // 2]
    W, w = circle_centre_weights(np.array(g.points_rz_mm).T, (g.r_mm, g.z_mm))
    dc = W @ (model.probe_matrix(np.array(g.points_rz_mm).T) @ u) + theta * w
    assert dc[0] == pytest.approx(theta * g.r_mm, rel=1e-8)
    assert dc[1] == pytest.approx(theta * (g.z_mm - z_fixed), rel=1e-8)


def test_grooves_follow_the_bearing_geometry_and_the_section_key_changes_with_them():
    a = grooved("seed000")
    geo = BearingGeometry.from_spec(a.bearing)
    d_i, d_o, _ = land_diameters_mm(a.bearing)
    sec = section_from_assembly(a)
    rings = {r.part: r for r in sec.rects if "ring" in r.part}
    assert rings["inner_ring_A"].r1_mm == pytest.approx(d_i / 2)
    assert rings["outer_ring_B"].r0_mm == pytest.approx(d_o / 2)
    for g, (ring, j) in zip(grooves_of(a), [("inner_ring_A", 0), ("inner_ring_B", 1),
                                             ("outer_ring_A", 0), ("outer_ring_B", 1)]):
        side = ring.split("_")[0]
        zb = ball_centres_rz_mm(a)[j][1]
        assert (g.r_mm, g.z_mm) == pytest.approx(groove_centre_rz_mm(geo, side, zb, SIGNS["DB"][j]))
        assert g.radius_mm == pytest.approx((geo.f_i if side == "inner" else geo.f_o) * geo.Dw_mm)
    rect = section_from_assembly(dataclasses.replace(
        a, mesh=dataclasses.replace(a.mesh, ring_section="rectangle")))
    assert rect.grooves == () and rect.key() != sec.key()
    deeper = dataclasses.replace(a, bearing=dataclasses.replace(a.bearing, inner_groove_ratio=0.53))
    assert section_from_assembly(deeper).key() != sec.key()


def test_ball_outline_is_a_circle_of_the_ball_diameter():
    pts = ball_outline_rz_mm(21.0, 3.5, 3.969)
    assert np.allclose(np.hypot(pts[:, 0] - 21.0, pts[:, 1] - 3.5), 3.969 / 2, rtol=1e-12)
    assert np.allclose(pts[0], pts[-1])


def test_bad_ring_section_and_grooved_geometry_are_one_line():
    import tomllib

    from studies.model.config import CONFIG_DIR
    raw = tomllib.loads((CONFIG_DIR / "seed000_71807C_TC4.toml").read_text())
    raw.setdefault("mesh", {})["ring_section"] = "round"
    with pytest.raises(ConfigError, match=r"mesh\.ring_section: 'round' is not one of") as e:
        assembly_from_dict(raw, "x.toml")
    assert "\n" not in str(e.value)
    raw["mesh"]["ring_section"] = "grooved"
    raw["bearing"]["width_mm"] = 4.0                  # 71807C: Dw 3.969 mm, f_i 0.52
    raw["bearing"]["inner_land_diameter_mm"] = 40.5   # land near the pitch circle: a groove
    #                                                   2 f_i Dw sin(81 deg) = 4.08 mm wide
    with pytest.raises(ConfigError, match=r"bearing\.inner_land_diameter_mm: the inner groove"):
        assembly_from_dict(raw, "x.toml")
    raw["mesh"]["ring_section"] = "rectangle"         # the effective sections do not care
    assembly_from_dict(raw, "x.toml")


def test_grooved_pipeline_superposed_equals_direct_and_fits_its_own_field():
    """seed000 grooved (coarse target): the superposed groove-centre shifts equal a direct FE
    solve per row, and equal the circle fitted to that row's full displacement field at the
    groove points (fem.post.circle_centre_weights on the field, not on the probes)."""
    from studies.model.pipeline import Pipeline, RINGS, table_inputs

    a = grooved("seed000")
    a = dataclasses.replace(a, mesh=dataclasses.replace(a.mesh, target_error=1e-2))
    pl = Pipeline(a)
    inp = table_inputs(a, {"T_ambient_C": np.array([-60.0, 80.0])})
    sup, direct = pl.fe(inp), pl.fe(inp, direct=True)
    scale = np.abs(direct.dr_mm).max()
    assert np.abs(sup.dr_mm - direct.dr_mm).max() <= 1e-8 * scale
    assert np.abs(sup.dz_mm - direct.dz_mm).max() <= 1e-8 * scale
    f = pl.field(inp, row=1)
    basis = pl.model.sbasis
    centre = []
    for ring in RINGS:
        g = pl.section.groove_of(ring)
        pts = np.array(g.points_rz_mm).T
        ur = basis.interpolator(f.u_mm[0::2])(pts)
        uz = basis.interpolator(f.u_mm[1::2])(pts)
        W, w = circle_centre_weights(pts, (g.r_mm, g.z_mm))
        theta = f.theta[list(pl.part_names).index(ring)]
        centre.append(W @ np.column_stack([ur, uz]).ravel() + theta * w)
    centre = np.array(centre)
    assert centre[0, 0] - centre[2, 0] == pytest.approx(sup.dr_mm[0, 1], rel=1e-9)
    assert centre[1, 1] - centre[3, 1] == pytest.approx(sup.dz_mm[1, 1], rel=1e-9)
