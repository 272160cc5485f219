"""The r-z section of an axisymmetric stack as named rectangles, before any meshing.

A `Section` is pure data: rectangles (parts, each with a material and a sub-assembly), the
raceway grooves cut into ring rectangles (`Groove`: a disc removed; none = rectangular rings), the
radial lines along which the inner-side and outer-side parts are separated ("splits": fits and free
sliding bores), the fits on them, roller supports, and the lines to refine. Everything not split is
tied (shared mesh nodes): clamped ring/spacer/shoulder/nut/cover faces; an axial split is tied in
u_z unless it is a `Face` (a clamp with a force: a unilateral contact with a spring in series).

Element sizes: `size_mm` in the bulk, `fit_size_mm` along the refined lines (fits, raceways) and,
when `corner_size_mm` > 0, a size graded down to `corner_size_mm` at the corner points: where a
fit or a clamped face ends. Those are the stress singularities of the stack (a ring corner on its
seat, the edge of a tied face, re-entrant shoulders); their error dominates the fit pressures and
the groove-centre shifts (studies/model/mesh_size.py has the measurements).

Coordinates: x = r (mm), y = z (mm).
"""
from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field, replace



@dataclass(frozen=True)
class Rect:
    part: str            # physical group name, e.g. "shaft", "inner_ring_A"
    r0_mm: float
    r1_mm: float
    z0_mm: float
    z1_mm: float
    material: str


@dataclass(frozen=True)
class Split:
    """A line along which the `outer_parts` get their own nodes, detached from the `inner_parts`.

    axis "r": the line r = at_mm, z in [lo_mm, hi_mm] (a seat or bore); node pairs are coupled only
    where a `Fit` says so, elsewhere they are free (a spacer bore sliding on the shaft).
    axis "z": the line z = at_mm, r in [lo_mm, hi_mm] (a clamped face: ring/spacer/shoulder/nut/
    cover); u_z is tied across it (the clamp holds the faces together) and u_r is free (the faces
    slide radially without friction, as a ring that was pressed on and then clamped does)."""
    name: str
    axis: str
    at_mm: float
    lo_mm: float
    hi_mm: float
    inner_parts: tuple[str, ...]
    outer_parts: tuple[str, ...]
    tied: bool = True                # axis "z" only: False = a compliant clamp, faces not tied


@dataclass(frozen=True)
class Fit:
    """A fit on a split line between `inner_part` (shaft/housing side is whichever is radially
    inside) and `outer_part`; `key` says which interference it takes ("inner" or "outer")."""
    name: str
    inner_part: str
    outer_part: str
    r_mm: float
    z0_mm: float
    z1_mm: float
    key: str


@dataclass(frozen=True)
class Face:
    """A clamped face as a unilateral contact (`[cover]`/`[nut]` clamp = "force"): the line
    z = z_mm, r in [r0_mm, r1_mm], on an axis-"z" split that is not tied. `inner_parts` are on the
    -z side, `outer_parts` on the +z side; the pair gap is u_z(outer) - u_z(inner) - delta (delta:
    the axial overlap the clamp is tightened with, `key` names it). In series with the contact a
    layer of springs of total stiffness 1 / compliance_mm_per_N (0: none), spread over the face
    as a uniform pressure is (the clamp's own spring: thread or bolts, `fem.model.face_weights`).

    A face of the stack itself (ring-shoulder, ring-spacer: key "stack", delta 0) has no spring
    in series; its `hold_ratio` > 0 holds each +z-side part to the -z side by a weak spring at
    one node pair, of stiffness hold_ratio x a steel part's axial stiffness (`fem.model`): a part
    whose faces all open keeps a position (it rests on its neighbour towards the shoulder, the
    stand-in for the fit friction that holds a loose ring), and the spring, unstretched while the
    face is closed, changes nothing then.
    """
    name: str
    inner_parts: tuple[str, ...]
    outer_parts: tuple[str, ...]
    z_mm: float
    r0_mm: float
    r1_mm: float
    key: str = "clamp"
    compliance_mm_per_N: float = 0.0
    hold_ratio: float = 0.0


@dataclass(frozen=True)
class Groove:
    """A raceway groove of a ring part: the disc of radius `radius_mm` about the groove curvature
    centre (r_mm, z_mm) is cut from the part's rectangle (it must leave the bore and the side
    faces whole). `fit_phi_deg`: angles (deg, at the centre, from the groove bottom) of the
    groove-surface points whose displacements give the groove-centre shift (`fem.post.
    circle_centre_weights`); `points_rz_mm` their (r, z) in mm (the same order)."""
    part: str
    r_mm: float
    z_mm: float
    radius_mm: float
    fit_phi_deg: tuple[float, ...]
    points_rz_mm: tuple[tuple[float, float], ...]
    size_mm: float = 0.0             # element size along the groove arc; 0 = the fit size


@dataclass(frozen=True)
class Section:
    rects: tuple[Rect, ...]
    splits: tuple[Split, ...] = ()
    fits: tuple[Fit, ...] = ()
    rollers_z_mm: tuple[float, ...] = ()       # u_z = 0 on these z = const lines (plane strain)
    refine_lines: tuple[tuple[float, float, float, float], ...] = ()  # (r0, z0, r1, z1)
    raceway_points: dict = field(default_factory=dict)  # ring part -> (r_mm, z_mm)
    size_mm: float = 1.0
    fit_size_mm: float = 0.25
    corner_size_mm: float = 0.0     # size at `corner_points()`, graded up to the others; 0 = none
    grooves: tuple[Groove, ...] = ()  # raceway grooves cut from ring rectangles; () = rectangles
    faces: tuple[Face, ...] = ()     # clamped faces as unilateral contacts (not in the mesh key)

    def parts(self) -> list[str]:
        seen = []
        for rc in self.rects:
            if rc.part not in seen:
                seen.append(rc.part)
        return seen

    def material_of(self, part: str) -> str:
        return next(rc.material for rc in self.rects if rc.part == part)

    def key(self) -> str:
        """Hash of everything that changes the mesh (geometry and sizes)."""
        data = json.dumps({"rects": [asdict(r) for r in self.rects],
                           "refine": self.refine_lines, "size": self.size_mm,
                           "fit_size": self.fit_size_mm,
                           "splits": [asdict(s) for s in self.splits]}, sort_keys=True)
        if self.corner_size_mm > 0:          # (sections without corner grading keep their keys)
            data += json.dumps({"corner_size": self.corner_size_mm})
        if self.grooves:                     # (rectangular sections keep their keys)
            data += json.dumps({"grooves": [asdict(g) for g in self.grooves]}, sort_keys=True)
        return hashlib.sha256(data.encode()).hexdigest()[:16]

    def scaled(self, factor: float) -> "Section":
        """Same geometry, a member of the same mesh family (refinement studies): the bulk and
        fit sizes multiplied by `factor`, the corner size by `factor`**2. At the singular corners
        the error falls only as (corner size)^0.75 (measured, studies/model/mesh_size.py); refined
        as the square, the family converges at one order (about 1.5 in `factor`) as a whole,
        which is what a Richardson extrapolation over its levels assumes."""
        return Section(self.rects, self.splits, self.fits, self.rollers_z_mm, self.refine_lines,
                       self.raceway_points, self.size_mm * factor, self.fit_size_mm * factor,
                       self.corner_size_mm * factor ** 2,
                       tuple(replace(g, size_mm=g.size_mm * factor) for g in self.grooves),
                       self.faces)

    def contact_names(self) -> tuple[str, ...]:
        """The FE contact interfaces in model order: the fits, then the faces."""
        return tuple(f.name for f in self.fits) + tuple(f.name for f in self.faces)

    def groove_of(self, part: str) -> "Groove | None":
        """The groove cut into `part`, or None (a rectangular ring, or not a ring)."""
        return next((g for g in self.grooves if g.part == part), None)

    def corner_points(self) -> list[tuple[float, float]]:
        """(r, z) in mm of every end of a fit and of a split line (seats, bores, clamped faces),
        without repeats: the points where a contact or tied interface ends."""
        pts = set()
        for f in self.fits:
            pts |= {(f.r_mm, f.z0_mm), (f.r_mm, f.z1_mm)}
        for s in self.splits:
            pts |= ({(s.lo_mm, s.at_mm), (s.hi_mm, s.at_mm)} if s.axis == "z"
                    else {(s.at_mm, s.lo_mm), (s.at_mm, s.hi_mm)})
        return sorted(pts)


def two_cylinder_section(r_inner_mm: float, r_fit_mm: float, r_outer_mm: float,
                         inner_material: str, outer_material: str, length_mm: float,
                         ring_length_mm: float | None = None, plane_strain: bool = False,
                         size_mm: float | None = None, fit_size_mm: float | None = None) -> Section:
    """Lamé verification geometry: an inner cylinder (solid if r_inner_mm == 0) with a ring fitted
    over z in [0, ring_length_mm] (default: the full length). `plane_strain` puts rollers (u_z = 0)
    on both end faces; otherwise the ends are free (the plane-stress Lamé solution is then exact
    for equal lengths with a frictionless fit, since sigma_r + sigma_theta is constant)."""
    L = length_mm
    Lr = L if ring_length_mm is None else ring_length_mm
    t = r_outer_mm - r_inner_mm
    size = size_mm if size_mm is not None else t / 8
    fsize = fit_size_mm if fit_size_mm is not None else size / 2
    rects = (Rect("shaft", r_inner_mm, r_fit_mm, 0.0, L, inner_material),
             Rect("inner_ring_A", r_fit_mm, r_outer_mm, 0.0, Lr, outer_material))
    splits = (Split("fit", "r", r_fit_mm, 0.0, Lr, ("shaft",), ("inner_ring_A",)),)
    fits = (Fit("fit", "shaft", "inner_ring_A", r_fit_mm, 0.0, Lr, "inner"),)
    rollers = (0.0, L) if plane_strain else ()
    return Section(rects, splits, fits, rollers, ((r_fit_mm, 0.0, r_fit_mm, Lr),),
                   {"inner_ring_A": (r_outer_mm, Lr / 2)}, size, fsize)


def boundary_lines(section: Section) -> dict[str, tuple[str, float, float, float]]:
    """Named outer boundary lines of a stack section: (axis, at, lo, hi) like a `Split`.
    Raceway lines are the ring surfaces facing the balls: of a grooved ring its groove arc, given
    as ("arc", r_c, z_c, radius) (the circle about (r_c, z_c) in mm; `fem.model.nodes_on_line`)."""
    lines = {}
    by_part = {}
    for rc in section.rects:
        by_part.setdefault(rc.part, []).append(rc)
    for ring, rp in section.raceway_points.items():
        rc = by_part[ring][0]
        g = section.groove_of(ring)
        lines[f"raceway_{ring}"] = (("r", rp[0], rc.z0_mm, rc.z1_mm) if g is None
                                    else ("arc", g.r_mm, g.z_mm, g.radius_mm))
    if "housing" in by_part:
        h = max(by_part["housing"], key=lambda r: r.r1_mm)
        lines["housing_outer"] = ("r", h.r1_mm, h.z0_mm, h.z1_mm)
    if "shaft" in by_part:
        s = by_part["shaft"][0]
        if s.r0_mm > 0:
            lines["shaft_bore"] = ("r", s.r0_mm, s.z0_mm, s.z1_mm)
        zs = max(r.z1_mm for r in by_part["shaft"])
        lines["shaft_end"] = ("z", zs, s.r0_mm, s.r1_mm)
    return lines
