"""Build the r-z mesh of a `Section` with gmsh; cache the .msh by a hash of geometry and sizes.

Every part is a named physical surface; every fit and every split line a named physical curve.
Elements are second-order triangles (triangle6), refined along fits and raceways. The mesh is read
back with meshio (`read_section_mesh`).
"""
from __future__ import annotations

import os
import shutil
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from meshes.section import Section


class MeshError(RuntimeError):
    """gmsh failed or the mesh is unusable; the message is one line."""


#: largest mesh built without asking (triangles; P2: about 4 DOF per triangle, ~4 kB of memory per
#: triangle through assembly and factorisation): BEARINGFEM_MAX_ELEMENTS overrides it
MAX_ELEMENTS = 400_000
#: temporary mesh files of killed runs older than this are removed whatever their PID (s)
STALE_AGE_S = 24 * 3600.0


def warn(msg: str) -> None:
    """One warning line on stderr (the run goes on)."""
    print(f"bearingfem: warning: {msg}", file=sys.stderr, flush=True)


def cache_dir() -> Path:
    """The mesh cache folder (BEARINGFEM_CACHE or ~/.cache/bearingfem, then meshes/). When it
    cannot be created or written, a private temporary folder serves this run (one warning)."""
    d = Path(os.environ.get("BEARINGFEM_CACHE", Path.home() / ".cache" / "bearingfem")) / "meshes"
    try:
        d.mkdir(parents=True, exist_ok=True)
        if not os.access(d, os.W_OK | os.X_OK):
            raise PermissionError(13, "not writable")
        return d
    except OSError as exc:
        tmp = Path(tempfile.mkdtemp(prefix="bearingfem-meshes-"))
        warn(f"mesh cache {d} is not usable ({exc.strerror or exc}); meshing in {tmp} for this run")
        return tmp


def estimate_elements(section: Section) -> int:
    """Triangles the mesh will have, from the section area at the coarse size (an equilateral
    triangle of side h has area 0.433 h^2) plus a band of 2 x 2 fit sizes along every refined line
    at the fit size."""
    coarse = sum((r.r1_mm - r.r0_mm) * (r.z1_mm - r.z0_mm) for r in section.rects)
    fine = sum(np.hypot(r1 - r0, z1 - z0) * 4.0 * section.fit_size_mm
               for r0, z0, r1, z1 in section.refine_lines)
    return int(coarse / (0.433 * section.size_mm ** 2) + fine / (0.433 * section.fit_size_mm ** 2))


def check_size(section: Section) -> int:
    """Refuse (MeshError, one line) a section whose mesh would exceed the element limit: a typo
    in a dimension or a mesh size would otherwise mesh until the machine runs out of memory."""
    limit = int(float(os.environ.get("BEARINGFEM_MAX_ELEMENTS", MAX_ELEMENTS)))
    n = estimate_elements(section)
    if n > limit:
        raise MeshError(f"the mesh would have about {n:.2g} triangles (~{4e-6 * n:.1f} GB), above "
                        f"the limit of {limit:.2g} (BEARINGFEM_MAX_ELEMENTS): check the section "
                        "dimensions and the [mesh] sizes")
    return n


def _remove_stale(d: Path) -> None:
    """Temporary meshes of killed runs: `section_<key>.<pid>.msh` whose process is gone (or that
    are older than STALE_AGE_S)."""
    now = time.time()
    for f in d.glob("section_*.*.msh"):
        try:
            pid = int(f.suffixes[-2][1:])
        except (ValueError, IndexError):
            continue
        try:
            alive = pid != os.getpid() and _pid_alive(pid)
            if not alive or now - f.stat().st_mtime > STALE_AGE_S:
                f.unlink()
        except OSError:
            pass


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


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
    d = cache_dir()
    _remove_stale(d)
    path = d / f"section_{section.key()}.msh"
    if (path.exists() or path.is_symlink()) and not refresh:
        try:
            return path, validated(path, section)
        except MeshError as exc:
            warn(f"cached mesh {path} is unusable ({exc}); rebuilding it")
            try:
                shutil.rmtree(path) if path.is_dir() and not path.is_symlink() else path.unlink()
            except OSError as exc2:
                raise MeshError(f"cannot remove the unusable cached mesh {path} "
                                f"({exc2.strerror})") from None
    tmp = path.with_suffix(f".{os.getpid()}.msh")
    try:
        _mesh_with_gmsh(section, tmp)
        try:
            mesh = validated(tmp, section)
        except MeshError as exc:
            raise MeshError(f"gmsh wrote an unusable mesh ({exc}); is the disk at {d} full?") from None
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
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


def _mesh_with_gmsh(section: Section, tmp: Path) -> None:
    import gmsh

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
        raise MeshError("no triangles in the mesh")
    t = np.vstack(tris)
    used = np.unique(t)
    remap = np.full(m.points.shape[0], -1)
    remap[used] = np.arange(used.size)
    pts = m.points[used, :2].T.copy()
    return SectionMesh(points=pts, triangles=remap[t].T.copy(), part_of=np.array(part),
                       lines={k: remap[np.array(v)].T for k, v in lines.items()}, path=path)
