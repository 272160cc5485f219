"""gmsh section mesh: named parts and interfaces, quadratic elements, cache by hash."""
import dataclasses

import meshio
import numpy as np

from meshes.build import build_mesh, read_section_mesh
from studies.model.stack import section_from_assembly
from studies.model.config import load_shipped


def test_named_groups_quadratic_and_cached():
    a = load_shipped("seed000")       # rectangular rings (grooved: tests/test_groove.py)
    a = dataclasses.replace(a, mesh=dataclasses.replace(a.mesh, ring_section="rectangle"))
    sec = section_from_assembly(a).scaled(3.0)
    path = build_mesh(sec)
    mtime = path.stat().st_mtime_ns
    assert build_mesh(sec) == path and path.stat().st_mtime_ns == mtime   # reused, not rebuilt
    raw = meshio.read(path)
    names = set(raw.field_data)
    assert set(sec.parts()) <= names
    assert {f.name for f in sec.fits} <= names
    assert {s.name for s in sec.splits if s.axis == "z"} <= names
    assert any(c.type == "triangle6" for c in raw.cells)
    m = read_section_mesh(path)
    # total section area equals the sum of the rectangles (no hole, no overlap)
    p, t = m.points, m.triangles
    area = 0.5 * np.abs((p[0, t[1]] - p[0, t[0]]) * (p[1, t[2]] - p[1, t[0]])
                        - (p[0, t[2]] - p[0, t[0]]) * (p[1, t[1]] - p[1, t[0]])).sum()
    rect = sum((r.r1_mm - r.r0_mm) * (r.z1_mm - r.z0_mm) for r in sec.rects)
    assert abs(area - rect) < 1e-9 * rect
    assert sec.scaled(0.5).key() != sec.key()
