"""Assembly config -> the r-z section the FE meshes: where every part of the stack sits.

The rotor (shaft, inner rings, inner spacer, nut) and the stator (housing, outer rings, outer
spacer, cover, and an optional sleeve and cartridge between outer rings and housing) as named
rectangles, the radial split lines (fits, sliding bores), the clamped
faces and the raceway points; the element sizes from `studies.model.mesh_size`. `meshes/` knows
only sections; this is the one place that reads an assembly to make one. Units: mm.

Ring sections (`[mesh] ring_section`): "grooved" cuts each ring's raceway groove, the
circle of radius f Dw about its curvature centre (`analytic.bearing.land.groove_centre_rz_mm`),
from a ring rectangle that reaches the land diameter (`land_diameters_mm`; the same land on both
sides of the groove); "rectangle" (the default) keeps the effective ring sections of `[bearing]`
(inner_ring_outer_diameter_mm, outer_ring_inner_diameter_mm) with the raceway on their faces.
"""
from __future__ import annotations

import numpy as np

from analytic.bearing.geometry import SIGNS, BearingGeometry
from analytic.bearing.land import (groove_centre_rz_mm, groove_point_rz_mm, land_angle_deg,
                                   land_diameters_mm)
from analytic.clamp import annulus_area_mm2, thread_clamp_stiffness_N_per_mm
from analytic.materials import get_material
from fem.model import HOLD_RATIO
from meshes.section import Face, Fit, Groove, Rect, Section, Split
from studies.model.config import Assembly
from studies.model.mesh_size import mesh_sizes

#: the rotor sub-assembly: the parts that spin with the shaft (centrifugal load in the FE)
ROTOR_PARTS = ("shaft", "inner_ring_A", "inner_spacer", "inner_ring_B", "nut")

#: the stack's own axial faces on each side (ring-shoulder, ring-spacer): tied (u_z) under a
#: rigid or compliant clamp; under a clamp with a force (`[nut]` for "inner", `[cover]` for
#: "outer") unilateral contacts like the clamp's own face (`meshes.section.Face`, key "stack",
#: no overlap, each part held by a weak spring, `fem.model.HOLD_RATIO`): they open when thermal
#: growth, fits or speed use the clamp force up
STACK_FACES = {"inner": ("face_shaft_shoulder", "face_inner_A_spacer", "face_inner_spacer_B"),
               "outer": ("face_housing_shoulder", "face_outer_A_spacer", "face_outer_spacer_B")}

#: half-width (deg, at the groove centre) of the groove arc about the free contact angle whose
#: displaced points give the groove-centre shift, and the number of points on it
GROOVE_FIT_HALF_ANGLE_DEG, GROOVE_FIT_POINTS = 30.0, 13
#: element size along a groove arc per fit size: the chords of the arc are the grooved section's
#: geometric error (sagitta h^2 / 8R), which converges at order 2 in h
GROOVE_SIZE_PER_FIT = 0.5


def ball_centres_rz_mm(a: Assembly) -> list[tuple[float, float]]:
    """(r, z) in mm of the ball centre of bearings A and B: the pitch radius at mid-width of the
    bearing's inner ring (the free geometry the groove centres are placed about)."""
    z = stack_positions(a)
    return [(a.bearing.pitch_diameter_mm / 2, sum(z[f"inner_ring_{J}"]) / 2) for J in "AB"]


def grooves_of(a: Assembly, size_mm: float = 0.0) -> tuple[Groove, ...]:
    """The four raceway grooves (inner_ring_A, inner_ring_B, outer_ring_A, outer_ring_B) of the
    assembly's stack: centres at the ball centre of each bearing (mid-width of its rings) plus the
    free-contact-line offsets (each ring's own mid-width taken as its ball-centre plane, as the
    rectangular sections' raceway points are), radius f Dw, and the points of the arc alpha0 +- 30 deg (kept
    inside the lands) that give the groove-centre shift."""
    g = BearingGeometry.from_spec(a.bearing, a.materials)
    lands = dict(zip(("inner", "outer"), land_diameters_mm(a.bearing, a.materials)[:2]))
    z = stack_positions(a)
    out = []
    for side in ("inner", "outer"):
        f = g.f_i if side == "inner" else g.f_o
        edge = 0.98 * land_angle_deg(g, side, lands[side])
        phi = np.linspace(max(g.alpha0_deg - GROOVE_FIT_HALF_ANGLE_DEG, -edge),
                          min(g.alpha0_deg + GROOVE_FIT_HALF_ANGLE_DEG, edge), GROOVE_FIT_POINTS)
        for j, J in enumerate("AB"):
            ring = f"{side}_ring_{J}"
            zb, s = sum(z[ring]) / 2, float(SIGNS[a.arrangement][j])
            rc, zc = groove_centre_rz_mm(g, side, zb, s)
            # 1e-6 of the radius into the ring: a point exactly on a mesh vertex of the arc
            # would be found outside every triangle by round-off (the fit stays exact for any
            # radius, fem.post.circle_centre_weights)
            pts = np.array([[rc], [zc]]) + (1 + 1e-6) * (groove_point_rz_mm(g, side, zb, s, phi)
                                                       - np.array([[rc], [zc]]))
            out.append(Groove(ring, float(rc), float(zc), f * g.Dw_mm, tuple(float(p) for p in phi),
                              tuple((float(r), float(zz)) for r, zz in pts.T), size_mm))
    return tuple(out)


def stack_positions(a: Assembly) -> dict[str, tuple[float, float]]:
    """Axial extent (z0, z1) in mm of every stack part; shoulder faces at z = 0."""
    B = a.bearing.width_mm
    zA, zS, zB = (0.0, B), (B, B + a.inner_spacer.length_mm), None
    zB = (zS[1], zS[1] + B)
    oS = (B, B + a.outer_spacer.length_mm)
    oB = (oS[1], oS[1] + B)
    return {"inner_ring_A": zA, "inner_spacer": zS, "inner_ring_B": zB,
            "nut": (zB[1], zB[1] + a.nut.width_mm),
            "outer_ring_A": (0.0, B), "outer_spacer": oS, "outer_ring_B": oB,
            "cover": (oB[1], oB[1] + a.cover.width_mm)}



def section_from_assembly(a: Assembly) -> Section:
    """Rectangles of the rotor (shaft, nut, inner rings, inner spacer) and the stator (housing,
    cover, outer rings, outer spacer) from an assembly config. Shoulder faces at z = 0."""
    s, h, b = a.shaft, a.housing, a.bearing
    B = b.width_mm
    z = stack_positions(a)
    r_seat, r_bore = s.seat_diameter_mm / 2, s.bore_diameter_mm / 2
    r_hb, r_ho = h.bore_diameter_mm / 2, h.outer_diameter_mm / 2
    z_nut_end = z["nut"][1]
    z_shaft_end = z_nut_end + s.extension_mm
    z_house_end = z["outer_ring_B"][1]
    grooved = a.mesh.ring_section == "grooved"
    if grooved:                     # the ring rectangles reach the lands; the grooves are cut
        r_iro, r_ori = (d / 2 for d in land_diameters_mm(b, a.materials)[:2])
    else:
        r_iro, r_ori = b.inner_ring_outer_diameter_mm / 2, b.outer_ring_inner_diameter_mm / 2
    rings = b.ring_material
    # sleeve / cartridge: cylinders from the bearing OD out to the housing bore, as long as the
    # outer-ring stack; the outer rings sit in the innermost one; their bores and outsides are
    # fits. Their end faces on the housing shoulder and the cover are clamped faces like the
    # rings' (u_z tied, sliding radially) with frictionless fits, and tied (shared nodes) with
    # bonded fits: every contact of the part bonded (a bonded sleeve of the housing's material
    # is then the housing itself)
    layers = [name for name, _ in a.layers()]
    r_od = a.outer_seat_diameter_mm / 2
    r_layer = [r_od]
    for _, layer in a.layers():
        r_layer.append(r_layer[-1] + layer.radial_thickness_mm)
    seat_of = (layers + ["housing"])          # the part each layer (and the rings) sits in
    sliding = layers if a.fits.contact == "frictionless" else []
    rects = [
        Rect("shaft", r_bore, r_seat, -s.shoulder_width_mm, z_shaft_end, s.material),
        Rect("shaft", r_seat, s.shoulder_diameter_mm / 2, -s.shoulder_width_mm, 0.0, s.material),
        Rect("inner_ring_A", r_seat, r_iro, *z["inner_ring_A"], rings),
        Rect("inner_spacer", r_seat, a.inner_spacer.diameter_mm / 2, *z["inner_spacer"],
             a.inner_spacer.material),
        Rect("inner_ring_B", r_seat, r_iro, *z["inner_ring_B"], rings),
        Rect("nut", r_seat, a.nut.diameter_mm / 2, *z["nut"], a.nut.material),
        Rect("housing", r_hb, r_ho, -h.shoulder_width_mm, z_house_end, h.material),
        Rect("housing", h.shoulder_diameter_mm / 2, r_hb, -h.shoulder_width_mm, 0.0, h.material),
        Rect("outer_ring_A", r_ori, r_od, *z["outer_ring_A"], rings),
        Rect("outer_spacer", a.outer_spacer.diameter_mm / 2, r_od, *z["outer_spacer"],
             a.outer_spacer.material),
        Rect("outer_ring_B", r_ori, r_od, *z["outer_ring_B"], rings),
        Rect("cover", a.cover.diameter_mm / 2, r_ho, *z["cover"], a.cover.material),
    ] + [Rect(name, r_layer[k], r_layer[k + 1], 0.0, z_house_end, layer.material)
         for k, (name, layer) in enumerate(a.layers())]
    outside = tuple(("housing", "cover") if p == "housing" else (p,) for p in seat_of)
    r_isp, r_osp = a.inner_spacer.diameter_mm / 2, a.outer_spacer.diameter_mm / 2
    zc = z["inner_ring_B"][0]
    # under a clamp with a force the stack's own faces on its side are contacts too (`STACK_FACES`)
    held = {"inner": a.nut.clamp != "force", "outer": a.cover.clamp != "force"}
    splits = (
        Split("shaft_seat", "r", r_seat, 0.0, z["inner_ring_B"][1], ("shaft", "nut"),
              ("inner_ring_A", "inner_spacer", "inner_ring_B")),
        Split("housing_bore", "r", r_od, 0.0, z_house_end, ("outer_ring_A", "outer_spacer",
                                                            "outer_ring_B"), outside[0]),
        *[Split(f"{name}_outside", "r", r_layer[k + 1], 0.0, z_house_end, (name,), outside[k + 1])
          for k, name in enumerate(layers)],
        Split("face_shaft_shoulder", "z", 0.0, r_seat, s.shoulder_diameter_mm / 2, ("shaft",),
              ("inner_ring_A",), held["inner"]),
        Split("face_inner_A_spacer", "z", B, r_seat, min(r_iro, r_isp), ("inner_ring_A",),
              ("inner_spacer",), held["inner"]),
        Split("face_inner_spacer_B", "z", zc, r_seat, min(r_iro, r_isp), ("inner_spacer",),
              ("inner_ring_B",), held["inner"]),
        Split("face_inner_B_nut", "z", z["nut"][0], r_seat, min(r_iro, a.nut.diameter_mm / 2),
              ("inner_ring_B",), ("nut",), a.nut.clamp == "rigid"),   # "force": a Face
        Split("face_housing_shoulder", "z", 0.0, h.shoulder_diameter_mm / 2, r_hb, ("housing",),
              ("outer_ring_A", *sliding), held["outer"]),
        Split("face_outer_A_spacer", "z", B, max(r_ori, r_osp), r_od, ("outer_ring_A",),
              ("outer_spacer",), held["outer"]),
        Split("face_outer_spacer_B", "z", z["outer_ring_B"][0], max(r_ori, r_osp), r_od,
              ("outer_spacer",), ("outer_ring_B",), held["outer"]),
        Split("face_outer_B_cover", "z", z["cover"][0], max(r_ori, a.cover.diameter_mm / 2), r_hb,
              ("outer_ring_B", *sliding), ("cover",), a.cover.clamp == "rigid"),
    )
    fits = tuple(
        [Fit(f"fit_inner_{j}", "shaft", f"inner_ring_{j}", r_seat, *z[f"inner_ring_{j}"], "inner")
         for j in "AB"]
        + [Fit(f"fit_outer_{j}", f"outer_ring_{j}", seat_of[0], r_od, *z[f"outer_ring_{j}"],
               "outer") for j in "AB"]
        + [Fit(f"fit_{name}", name, seat_of[k + 1], r_layer[k + 1], 0.0, z_house_end, name)
           for k, name in enumerate(layers)])
    refine = tuple((f.r_mm, f.z0_mm, f.r_mm, f.z1_mm) for f in fits)
    if grooved:     # raceway point: the middle of the fitted arc (the free contact point unless a
        #             land clips the arc)
        grooves = grooves_of(a, GROOVE_SIZE_PER_FIT * mesh_sizes(a).fit_size_mm)
        raceways = {gr.part: gr.points_rz_mm[len(gr.points_rz_mm) // 2] for gr in grooves}
    else:
        grooves = ()
        refine += tuple((r, z[f"{ring}_{j}"][0], r, z[f"{ring}_{j}"][1])
                        for ring, r in (("inner_ring", r_iro), ("outer_ring", r_ori)) for j in "AB")
        raceways = {f"inner_ring_{j}": (r_iro, sum(z[f"inner_ring_{j}"]) / 2) for j in "AB"}
        raceways.update({f"outer_ring_{j}": (r_ori, sum(z[f"outer_ring_{j}"]) / 2) for j in "AB"})
    sizes = mesh_sizes(a)
    faces = tuple(Face(f"face_clamp_{name}", split.inner_parts, split.outer_parts, split.at_mm,
                       split.lo_mm, split.hi_mm, f"clamp_{name}",
                       1.0 / clamp_stiffness_N_per_mm(a, name))
                  for name, split in (("nut", next(x for x in splits if x.name == "face_inner_B_nut")),
                                      ("cover", next(x for x in splits
                                                     if x.name == "face_outer_B_cover")))
                  if getattr(a, name).clamp == "force")
    faces += tuple(Face(x.name, x.inner_parts, x.outer_parts, x.at_mm, x.lo_mm, x.hi_mm, "stack",
                        0.0, HOLD_RATIO)
                   for side in ("inner", "outer") if not held[side]
                   for x in splits if x.name in STACK_FACES[side])
    return Section(tuple(rects), splits, fits, (), refine, raceways, sizes.size_mm,
                   sizes.fit_size_mm, sizes.corner_size_mm, grooves, faces)


def clamp_stiffness_N_per_mm(a: Assembly, name: str) -> float:
    """The stiffness (N/mm) of the clamp `name` ("nut" or "cover") in series with its face:
    `clamp_stiffness_N_per_um` when given, else from the part's section
    (`analytic.clamp.thread_clamp_stiffness_N_per_mm`): the nut on a thread of the shaft seat
    diameter (shaft annulus seat/bore, nut annulus nut/seat), the cover on a thread (or bolt
    circle) at the housing bore diameter (housing wall annulus outer/bore, cover annulus
    bore/cover inner diameter). The FE ties nut and cover to shaft and housing, so the thread's
    compliance is not counted twice."""
    c = getattr(a, name)
    if c.clamp_stiffness_N_per_um > 0:
        return 1e3 * c.clamp_stiffness_N_per_um
    E_clamp = get_material(c.material, a.materials).E_MPa
    if name == "nut":
        d = a.shaft.seat_diameter_mm
        return thread_clamp_stiffness_N_per_mm(
            d, get_material(a.shaft.material, a.materials).E_MPa,
            annulus_area_mm2(d, a.shaft.bore_diameter_mm), E_clamp,
            annulus_area_mm2(c.diameter_mm, d))
    d = a.housing.bore_diameter_mm
    return thread_clamp_stiffness_N_per_mm(
        d, get_material(a.housing.material, a.materials).E_MPa,
        annulus_area_mm2(a.housing.outer_diameter_mm, d), E_clamp,
        annulus_area_mm2(d, c.diameter_mm))
