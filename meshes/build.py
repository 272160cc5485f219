"""Build the r-z mesh of a `Section` with gmsh; cache the .msh by a hash of geometry and sizes.

Every part is a named physical surface; every fit and every split line a named physical curve.
Elements are second-order triangles (triangle6), refined along fits and raceways. The mesh is read
back with meshio (`read_section_mesh`).
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from meshes.section import Section


class MeshError(RuntimeError):
    """gmsh failed or the mesh is unusable; the message is one line."""


def cache_dir() -> Path:
    d = Path(os.environ.get("BEARINGFEM_CACHE", Path.home() / ".cache" / "bearingfem")) / "meshes"
    d.mkdir(parents=True, exist_ok=True)
    return d


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
    """Mesh `section` with gmsh (or reuse the cached file). Returns the .msh path."""
    path = cache_dir() / f"section_{section.key()}.msh"
    if path.exists() and not refresh:
        return path
    import gmsh

    tmp = path.with_suffix(f".{os.getpid()}.msh")
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        gmsh.model.add("section")
        tags = [occ.addRectangle(r.r0_mm, r.z0_mm, 0.0, r.r1_mm - r.r0_mm, r.z1_mm - r.z0_mm)
                for r in section.rects]
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

        gmsh.option.setNumber("Mesh.MeshSizeMax", section.size_mm)
        gmsh.option.setNumber("Mesh.MeshSizeMin", section.fit_size_mm)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        fine = [c for line in section.refine_lines for c in curves_on(*line)]
        field = gmsh.model.mesh.field
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
            field.setAsBackgroundMesh(thr)
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
    os.replace(tmp, path)
    return path


def read_section_mesh(path: Path) -> SectionMesh:
    """Read a section .msh with meshio: corner nodes of the triangle6 cells, the part of each
    triangle (physical surface names) and the named physical curves (line3 -> corner pairs)."""
    import contextlib
    import io

    import meshio

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
        raise MeshError(f"{path}: no triangles in the mesh")
    t = np.vstack(tris)
    used = np.unique(t)
    remap = np.full(m.points.shape[0], -1)
    remap[used] = np.arange(used.size)
    pts = m.points[used, :2].T.copy()
    return SectionMesh(points=pts, triangles=remap[t].T.copy(), part_of=np.array(part),
                       lines={k: remap[np.array(v)].T for k, v in lines.items()}, path=path)
