"""The r-z section of an axisymmetric stack as named rectangles, before any meshing.

A `Section` is pure data: rectangles (parts, each with a material and a sub-assembly), the
radial lines along which the inner-side and outer-side parts are separated ("splits": fits and free
sliding bores), the fits on them, roller supports, and the lines to refine. Everything not split is
tied (shared mesh nodes): clamped ring/spacer/shoulder/nut/cover faces.

Coordinates: x = r (mm), y = z (mm).
"""
from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field

from studies.config import Assembly, stack_positions


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
class Section:
    rects: tuple[Rect, ...]
    splits: tuple[Split, ...] = ()
    fits: tuple[Fit, ...] = ()
    rollers_z_mm: tuple[float, ...] = ()       # u_z = 0 on these z = const lines (plane strain)
    refine_lines: tuple[tuple[float, float, float, float], ...] = ()  # (r0, z0, r1, z1)
    raceway_points: dict = field(default_factory=dict)  # ring part -> (r_mm, z_mm)
    size_mm: float = 1.0
    fit_size_mm: float = 0.25

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
        return hashlib.sha256(data.encode()).hexdigest()[:16]

    def scaled(self, factor: float) -> "Section":
        """Same geometry, element sizes multiplied by `factor` (mesh refinement studies)."""
        return Section(self.rects, self.splits, self.fits, self.rollers_z_mm, self.refine_lines,
                       self.raceway_points, self.size_mm * factor, self.fit_size_mm * factor)


ROTOR = ("shaft", "nut", "inner_ring_A", "inner_spacer", "inner_ring_B")
STATOR = ("housing", "cover", "outer_ring_A", "outer_spacer", "outer_ring_B")


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
    r_iro, r_ori = b.inner_ring_outer_diameter_mm / 2, b.outer_ring_inner_diameter_mm / 2
    rings = b.ring_material
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
        Rect("outer_ring_A", r_ori, r_hb, *z["outer_ring_A"], rings),
        Rect("outer_spacer", a.outer_spacer.diameter_mm / 2, r_hb, *z["outer_spacer"],
             a.outer_spacer.material),
        Rect("outer_ring_B", r_ori, r_hb, *z["outer_ring_B"], rings),
        Rect("cover", a.cover.diameter_mm / 2, r_ho, *z["cover"], a.cover.material),
    ]
    r_isp, r_osp = a.inner_spacer.diameter_mm / 2, a.outer_spacer.diameter_mm / 2
    zc = z["inner_ring_B"][0]
    splits = (
        Split("shaft_seat", "r", r_seat, 0.0, z["inner_ring_B"][1], ("shaft", "nut"),
              ("inner_ring_A", "inner_spacer", "inner_ring_B")),
        Split("housing_bore", "r", r_hb, 0.0, z_house_end, ("outer_ring_A", "outer_spacer",
                                                            "outer_ring_B"), ("housing", "cover")),
        Split("face_shaft_shoulder", "z", 0.0, r_seat, s.shoulder_diameter_mm / 2, ("shaft",),
              ("inner_ring_A",)),
        Split("face_inner_A_spacer", "z", B, r_seat, min(r_iro, r_isp), ("inner_ring_A",),
              ("inner_spacer",)),
        Split("face_inner_spacer_B", "z", zc, r_seat, min(r_iro, r_isp), ("inner_spacer",),
              ("inner_ring_B",)),
        Split("face_inner_B_nut", "z", z["nut"][0], r_seat, min(r_iro, a.nut.diameter_mm / 2),
              ("inner_ring_B",), ("nut",), a.nut.clamp == "rigid"),
        Split("face_housing_shoulder", "z", 0.0, h.shoulder_diameter_mm / 2, r_hb, ("housing",),
              ("outer_ring_A",)),
        Split("face_outer_A_spacer", "z", B, max(r_ori, r_osp), r_hb, ("outer_ring_A",),
              ("outer_spacer",)),
        Split("face_outer_spacer_B", "z", z["outer_ring_B"][0], max(r_ori, r_osp), r_hb,
              ("outer_spacer",), ("outer_ring_B",)),
        Split("face_outer_B_cover", "z", z["cover"][0], max(r_ori, a.cover.diameter_mm / 2), r_hb,
              ("outer_ring_B",), ("cover",), a.cover.clamp == "rigid"),
    )
    fits = tuple(
        [Fit(f"fit_inner_{j}", "shaft", f"inner_ring_{j}", r_seat, *z[f"inner_ring_{j}"], "inner")
         for j in "AB"]
        + [Fit(f"fit_outer_{j}", f"outer_ring_{j}", "housing", r_hb, *z[f"outer_ring_{j}"], "outer")
           for j in "AB"])
    refine = tuple((f.r_mm, f.z0_mm, f.r_mm, f.z1_mm) for f in fits) + tuple(
        (r, z[f"{ring}_{j}"][0], r, z[f"{ring}_{j}"][1])
        for ring, r in (("inner_ring", r_iro), ("outer_ring", r_ori)) for j in "AB")
    raceways = {f"inner_ring_{j}": (r_iro, sum(z[f"inner_ring_{j}"]) / 2) for j in "AB"}
    raceways.update({f"outer_ring_{j}": (r_ori, sum(z[f"outer_ring_{j}"]) / 2) for j in "AB"})
    return Section(tuple(rects), splits, fits, (), refine, raceways, a.mesh.size_mm,
                   a.mesh.fit_size_mm)


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
