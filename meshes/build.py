"""Build the r-z mesh of a `Section` with gmsh; cache the .msh by a hash of geometry and sizes
(`meshes.cache`: checked on every read, written atomically).

Every part is a named physical surface; every fit and every split line a named physical curve.
Elements are second-order triangles (triangle6), refined along fits and raceways. The mesh is read
back with meshio (`read_section_mesh`).
"""
from __future__ import annotations

import contextlib
import io
import os
import signal
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from meshes.cache import cache_dir, cached_file
from meshes.section import Section


class MeshError(RuntimeError):
    """gmsh failed or the mesh is unusable; the message is one line."""


#: largest mesh built without asking (triangles; P2: about 4 DOF per triangle, ~4 kB of memory per
#: triangle through assembly and factorisation): BEARINGFEM_MAX_ELEMENTS overrides it
MAX_ELEMENTS = 400_000
#: right-hand sides per solve when `fem.solver.condense` condenses the fits (set here, where the
#: size guard budgets its memory): DOFs x 32 float64 per array, 4 kB per triangle in all, whatever
#: the number of contact pairs (before, DOFs x pairs: 3-6 GB for a 0.25-scaled grooved mesh)
CONDENSE_BLOCK = 32
#: growth of the element size away from a corner point: size = corner size + CORNER_GRADE x
#: distance (0.5: as accurate per DOF as 0.3 and 0.8 on the seed 000 and 305-size stacks, and the
#: smoothest convergence of the three; studies/model/mesh_size.py)
CORNER_GRADE = 0.5


def estimate_elements(section: Section) -> int:
    """Triangles the mesh will have, from the section area at the coarse size (an equilateral
    triangle of side h has area 0.433 h^2) plus a band of 2 x 2 fit sizes along every refined line
    at the fit size, plus a disc around every corner point graded from the corner size to the
    fit size (size g rho at distance rho: 2 pi / (0.433 g^2) ln(fit / corner) triangles; an upper
    bound, corners are rarely surrounded by material on all sides)."""
    coarse = sum((r.r1_mm - r.r0_mm) * (r.z1_mm - r.z0_mm) for r in section.rects)
    fine = sum(np.hypot(r1 - r0, z1 - z0) * 4.0 * section.fit_size_mm
               for r0, z0, r1, z1 in section.refine_lines)
    n = coarse / (0.433 * section.size_mm ** 2) + fine / (0.433 * section.fit_size_mm ** 2)
    if 0 < section.corner_size_mm < section.fit_size_mm:
        n += (len(section.corner_points()) * 2 * np.pi / (0.433 * CORNER_GRADE ** 2)
              * np.log(section.fit_size_mm / section.corner_size_mm))
    return int(n)


def estimate_memory_GB(section: Section, n_triangles: int) -> float:
    """Memory of the FE set-up, GB: ~4 kB per triangle (assembly, factorisation) plus the
    condensation of the fits (`fem.solver.condense`): four float64 arrays of DOFs x
    CONDENSE_BLOCK right-hand sides while a block is solved (P2: about 4 DOF per triangle), and
    three of contact pairs x pairs kept (a pair per half fit size along each fit; the flexibility
    and the pair rows of the solutions). The second term dominates for thin sections (a 0.1 mm
    ring: 1362 pairs)."""
    pairs = sum((f.z1_mm - f.z0_mm) / (0.5 * section.fit_size_mm) + 1 for f in section.fits)
    return 4e-6 * n_triangles + 8e-9 * (4 * (4 * n_triangles) * CONDENSE_BLOCK + 3 * pairs ** 2)


def check_size(section: Section) -> int:
    """Refuse (MeshError, one line) a section whose mesh would exceed the element limit or the
    memory that many triangles take: a typo in a dimension or a mesh size would otherwise mesh
    and condense until the machine runs out of memory."""
    limit = int(float(os.environ.get("BEARINGFEM_MAX_ELEMENTS", MAX_ELEMENTS)))
    n = estimate_elements(section)
    gb = estimate_memory_GB(section, n)
    if n > limit or gb > 4e-6 * limit:
        raise MeshError(f"the mesh would have about {n:.2g} triangles (~{gb:.1f} GB with its fits' "
                        f"condensation), above the limit of {limit:.2g} triangles (~{4e-6 * limit:.1f} "
                        "GB; BEARINGFEM_MAX_ELEMENTS): check the section dimensions and the [mesh] sizes")
    return n


@dataclass
class SectionMesh:
    """Mesh arrays: points (2, n) in mm (r, z), triangles (3, m) corner nodes, part name per
    triangle, named line segments (name -> (2, k) corner-node pairs)."""
    points: np.ndarray
    triangles: np.ndarray
    part_of: np.ndarray
    lines: dict
    path: Path


def build_mesh(section: Section, refresh: bool = False) -> Path:
    """Mesh `section` with gmsh, or reuse the cached file when it reads back as this section's
    mesh. Returns the .msh path (see `section_mesh` for the validated mesh itself)."""
    return _cached(section, refresh)[0]


def section_mesh(section: Section) -> "SectionMesh":
    """The validated mesh of `section`: from the cache when it is sound (a damaged, truncated or
    foreign file there is rebuilt with one warning), else meshed now."""
    return _cached(section, False)[1]


def _cached(section: Section, refresh: bool):
    check_size(section)
    d = cache_dir("meshes", "mesh")
    path = d / f"section_{section.key()}.msh"
    mesh = cached_file(path, lambda tmp: _mesh_with_gmsh(section, tmp),
                       lambda p: validated(p, section), what="mesh", writer="gmsh",
                       error=MeshError, refresh=refresh)
    mesh.path = path
    return path, mesh


def validated(path: Path, section: Section) -> "SectionMesh":
    """Read a .msh and check it is the mesh of `section`: readable, triangles present, every part
    and every fit line of the section named in it, its extent equal to the section's."""
    try:
        mesh = read_section_mesh(path)
    except MeshError:
        raise
    except Exception as exc:  # meshio raises many kinds on a damaged file
        raise MeshError(f"unreadable: {type(exc).__name__}") from None
    if set(mesh.part_of) != set(section.parts()):
        raise MeshError("its parts are not this section's")
    missing = [f.name for f in section.fits if f.name not in mesh.lines]
    if missing:
        raise MeshError(f"fit line {missing[0]} missing")
    r0 = min(r.r0_mm for r in section.rects)
    r1 = max(r.r1_mm for r in section.rects)
    z0 = min(r.z0_mm for r in section.rects)
    z1 = max(r.z1_mm for r in section.rects)
    lo, hi = mesh.points.min(axis=1), mesh.points.max(axis=1)
    tol = 1e-9 * max(r1 - r0, z1 - z0)
    if not (np.allclose(lo, (r0, z0), rtol=0, atol=tol) and np.allclose(hi, (r1, z1), rtol=0, atol=tol)):
        raise MeshError("its extent is not this section's")
    return mesh


def restore_signal_handlers() -> None:
    """Set the C-level handlers of SIGTERM and SIGPIPE back to what Python has installed.

    `gmsh.initialize` resets both to their defaults (measured with sigaction: SIGTERM from
    Python's handler to SIG_DFL, SIGPIPE from SIG_IGN to SIG_DFL), so from the first mesh on a
    SIGTERM killed the process outright, leaving its temporary output file, folder and mesh behind,
    and a closed pipe killed it silently. Only the main thread may set handlers; elsewhere (a Dask
    worker thread) this does nothing."""
    if threading.current_thread() is not threading.main_thread():
        return
    for sig in (signal.SIGTERM, signal.SIGPIPE):
        handler = signal.getsignal(sig)
        if handler is not None:
            signal.signal(sig, handler)


def _mesh_with_gmsh(section: Section, tmp: Path) -> None:
    import gmsh  # noqa: PLC0415 -- deferred: gmsh loads a large native library, meshing is rare

    gmsh.initialize(interruptible=False)
    restore_signal_handlers()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        gmsh.model.add("section")
        tags = [occ.addRectangle(r.r0_mm, r.z0_mm, 0.0, r.r1_mm - r.r0_mm, r.z1_mm - r.z0_mm)
                for r in section.rects]
        tags = _cut_grooves(occ, section, tags)
        occ.fragment([(2, t) for t in tags], [])
        occ.synchronize()
        parts = section.parts()
        groups: dict[str, list[int]] = {p: [] for p in parts}
        for dim, tag in gmsh.model.getEntities(2):
            cx, cy, _ = occ.getCenterOfMass(dim, tag)
            owner = [r.part for r in section.rects
                     if r.r0_mm <= cx <= r.r1_mm and r.z0_mm <= cy <= r.z1_mm]
            if len(owner) != 1:
                raise MeshError(f"surface at r={cx:.3f}, z={cy:.3f} mm belongs to {owner or 'no part'}:"
                                " parts overlap or leave a hole")
            groups[owner[0]].append(tag)
        for p, surf in groups.items():
            gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, surf), p)

        def curves_on(r0, z0, r1, z1):
            found = []
            for _, c in gmsh.model.getEntities(1):
                xmin, ymin, _, xmax, ymax, _ = gmsh.model.getBoundingBox(1, c)
                tol = 1e-7 * (1 + abs(xmax) + abs(ymax))
                if (min(r0, r1) - tol <= xmin and xmax <= max(r0, r1) + tol
                        and min(z0, z1) - tol <= ymin and ymax <= max(z0, z1) + tol):
                    found.append(c)
            return found

        for f in section.fits:
            cs = curves_on(f.r_mm, f.z0_mm, f.r_mm, f.z1_mm)
            gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, cs), f.name)
        for s in section.splits:
            if s.axis == "z":   # clamped faces; seat/bore lines are covered by the fits
                cs = curves_on(s.lo_mm, s.at_mm, s.hi_mm, s.at_mm)
                gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, cs), s.name)

        corner = section.corner_size_mm
        gmsh.option.setNumber("Mesh.MeshSizeMax", section.size_mm)
        gmsh.option.setNumber("Mesh.MeshSizeMin", min([corner or section.fit_size_mm,
                                                       section.fit_size_mm]
                                                      + [g.size_mm for g in section.grooves
                                                         if g.size_mm > 0]))
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        fine = [c for line in section.refine_lines for c in curves_on(*line)]
        field = gmsh.model.mesh.field
        fields = []
        if fine:
            dist = field.add("Distance")
            field.setNumbers(dist, "CurvesList", fine)
            field.setNumber(dist, "Sampling", 200)
            thr = field.add("Threshold")
            field.setNumber(thr, "InField", dist)
            field.setNumber(thr, "SizeMin", section.fit_size_mm)
            field.setNumber(thr, "SizeMax", section.size_mm)
            field.setNumber(thr, "DistMin", 2 * section.fit_size_mm)
            field.setNumber(thr, "DistMax", 2 * section.fit_size_mm + 4 * section.size_mm)
            fields.append(thr)
        for g in section.grooves:            # the groove arc at its own size (its chords
            arc = field.add("Distance")      # are the section's only geometric error)
            field.setNumbers(arc, "CurvesList", _arc_curves(gmsh, g))
            field.setNumber(arc, "Sampling", 200)
            h = g.size_mm or section.fit_size_mm
            thr = field.add("Threshold")
            field.setNumber(thr, "InField", arc)
            field.setNumber(thr, "SizeMin", h)
            field.setNumber(thr, "SizeMax", section.size_mm)
            field.setNumber(thr, "DistMin", 2 * h)
            field.setNumber(thr, "DistMax", 2 * h + (section.size_mm - h) / CORNER_GRADE)
            fields.append(thr)
        if corner > 0:                       # graded towards the singular corners
            near = field.add("Distance")
            field.setNumbers(near, "PointsList", _point_tags(gmsh, section.corner_points()))
            grade = field.add("Threshold")
            field.setNumber(grade, "InField", near)
            field.setNumber(grade, "SizeMin", corner)
            field.setNumber(grade, "SizeMax", section.size_mm)
            field.setNumber(grade, "DistMin", 0.0)
            field.setNumber(grade, "DistMax", (section.size_mm - corner) / CORNER_GRADE)
            fields.append(grade)
        if len(fields) == 1:
            field.setAsBackgroundMesh(fields[0])
        elif fields:
            smallest = field.add("Min")
            field.setNumbers(smallest, "FieldsList", fields)
            field.setAsBackgroundMesh(smallest)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(tmp))
    except MeshError:
        raise
    except Exception as exc:  # gmsh raises plain Exception with its last error
        raise MeshError(f"gmsh failed to mesh the section: {exc}") from None
    finally:
        gmsh.finalize()


def _cut_grooves(occ, section: Section, tags: list[int]) -> list[int]:
    """The rectangle tags with every groove disc cut from its ring's (first) rectangle. The
    disc must leave the ring one piece whose extent is the rectangle's (bore and faces whole)."""
    tags = list(tags)
    for g in section.grooves:
        i = next(k for k, r in enumerate(section.rects) if r.part == g.part)
        r = section.rects[i]
        disk = occ.addDisk(g.r_mm, g.z_mm, 0.0, g.radius_mm, g.radius_mm)
        out, _ = occ.cut([(2, tags[i])], [(2, disk)])
        box = occ.getBoundingBox(*out[0]) if len(out) == 1 else None
        tol = 1e-6 * (1 + r.r1_mm)
        if box is None or not np.allclose([box[0], box[1], box[3], box[4]],
                                          [r.r0_mm, r.z0_mm, r.r1_mm, r.z1_mm], atol=tol, rtol=0):
            raise MeshError(f"the groove of {g.part} (centre r={g.r_mm:g}, z={g.z_mm:g} mm, radius "
                            f"{g.radius_mm:g} mm) cuts through its ring's bore or side faces")
        tags[i] = out[0][1]
    return tags


def _arc_curves(gmsh, g) -> list[int]:
    """The curves of the meshed geometry lying on the groove circle of `g` (checked at both ends
    and the middle of each curve's parameter range)."""
    found = []
    for _, c in gmsh.model.getEntities(1):
        lo, hi = gmsh.model.getParametrizationBounds(1, c)
        xyz = np.reshape(gmsh.model.getValue(1, c, [lo[0], 0.5 * (lo[0] + hi[0]), hi[0]]), (3, 3))
        d = np.hypot(xyz[:, 0] - g.r_mm, xyz[:, 1] - g.z_mm)
        if np.all(np.abs(d - g.radius_mm) < 1e-7 * (1 + g.radius_mm)):
            found.append(c)
    if not found:
        raise MeshError(f"the groove of {g.part} is not a curve of the meshed section")
    return found


def _point_tags(gmsh, points: list[tuple[float, float]]) -> list[int]:
    """The gmsh point entities at the given (r, z) in mm (every corner point of a section is a
    rectangle corner, so a vertex of the fragmented geometry)."""
    tags, found = [], set()
    for _, tag in gmsh.model.getEntities(0):
        x, y, _ = gmsh.model.getValue(0, tag, [])
        for p in points:
            if abs(x - p[0]) <= 1e-7 * (1 + abs(p[0])) and abs(y - p[1]) <= 1e-7 * (1 + abs(p[1])):
                tags.append(tag)
                found.add(p)
    missing = [p for p in points if p not in found]
    if missing:
        raise MeshError(f"corner point r={missing[0][0]:g}, z={missing[0][1]:g} mm is not a vertex "
                        "of the section")
    return tags


def read_section_mesh(path: Path) -> SectionMesh:
    """Read a section .msh with meshio: corner nodes of the triangle6 cells, the part of each
    triangle (physical surface names) and the named physical curves (line3 -> corner pairs)."""
    import meshio  # noqa: PLC0415 -- deferred: a run with its FE set-up cached never reads a mesh

    with contextlib.redirect_stdout(io.StringIO()):      # meshio prints a stray blank line
        m = meshio.read(str(path))
    id_to_name = {int(v[0]): k for k, v in m.field_data.items()}
    tris, part, lines = [], [], {}
    for block, phys in zip(m.cells, m.cell_data["gmsh:physical"]):
        if block.type in ("triangle6", "triangle"):
            tris.append(block.data[:, :3])
            part.extend(id_to_name[int(i)] for i in phys)
        elif block.type in ("line3", "line"):
            for seg, i in zip(block.data[:, :2], phys):
                lines.setdefault(id_to_name[int(i)], []).append(seg)
    if not tris:
        raise MeshError("no triangles in the mesh")
    t = np.vstack(tris)
    used = np.unique(t)
    remap = np.full(m.points.shape[0], -1)
    remap[used] = np.arange(used.size)
    pts = m.points[used, :2].T.copy()
    return SectionMesh(points=pts, triangles=remap[t].T.copy(), part_of=np.array(part),
                       lines={k: remap[np.array(v)].T for k, v in lines.items()}, path=path)
