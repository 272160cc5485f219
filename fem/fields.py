"""Field export: VTU files (ParaView) and off-screen pyvista images, one PNG per field.

The r-z section is written as a flat mesh in the x-y plane (x = r, y = z, mm). Point data:
displacement (mm) and temperature (C); cell data: stresses (MPa) and the part index.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fem.model import StackModel
from infra.signals import deferred_signals


def vertex_values(model: StackModel, u: np.ndarray) -> np.ndarray:
    """(n_vertices, 2) displacement at the mesh vertices (P2 nodal DOFs)."""
    nd = model.basis.nodal_dofs
    return np.column_stack([u[nd[0]], u[nd[1]]])


def write_vtu(path: Path, model: StackModel, u: np.ndarray, cell_data: dict[str, np.ndarray],
              T_vertex_C: np.ndarray | None = None) -> Path:
    """Write the deformed-state fields of one solution to a .vtu file (meshio)."""
    import meshio  # noqa: PLC0415 -- deferred: only VTU output needs it

    pts = np.column_stack([model.mesh.p.T, np.zeros(model.mesh.p.shape[1])])
    disp = vertex_values(model, u)
    point_data = {"displacement_mm": np.column_stack([disp, np.zeros(len(disp))])}
    if T_vertex_C is not None:
        point_data["temperature_C"] = T_vertex_C
    parts = {p: i for i, p in enumerate(model.part_names)}
    cells = {k: [np.asarray(v, float)] for k, v in cell_data.items()}
    cells["part"] = [np.array([parts[p] for p in model.part_of], float)]
    meshio.write(str(path), meshio.Mesh(pts, [("triangle", model.mesh.t.T)],
                                        point_data=point_data, cell_data=cells))
    return path


def _grid(model: StackModel, pts_xy: np.ndarray):
    import pyvista as pv  # noqa: PLC0415 -- deferred: pyvista/VTK load only for images

    t = model.mesh.t.T
    cells = np.hstack([np.full((t.shape[0], 1), 3), t]).ravel()
    celltypes = np.full(t.shape[0], pv.CellType.TRIANGLE, dtype=np.uint8)
    return pv.UnstructuredGrid(cells, celltypes, np.column_stack([pts_xy, np.zeros(len(pts_xy))]))


def part_label_points(model: StackModel, pts_xy: np.ndarray) -> tuple[np.ndarray, list[str]]:
    """One label point per part (mm): the vertex of the part nearest to its area centroid, so
    the label sits on the part even where a section is not convex."""
    t = model.mesh.t.T
    corners = pts_xy[t]                                        # (n_cells, 3, 2)
    centroid = corners.mean(axis=1)
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    where, names = [], []
    for name in model.part_names:
        on = model.part_of == name
        if not on.any():
            continue
        c = (centroid[on] * area[on, None]).sum(axis=0) / area[on].sum()
        near = centroid[on][np.argmin(np.linalg.norm(centroid[on] - c, axis=1))]
        where.append(near)
        names.append(name)
    return np.array(where), names


def scale_bar_mm(extent_mm: float) -> float:
    """A round scale-bar length (1, 2 or 5 x 10^k mm) about a fifth of the drawing's extent."""
    target = 0.2 * extent_mm
    k = np.floor(np.log10(target))
    return float(min((m * 10 ** k for m in (1, 2, 5)), key=lambda v: abs(v - target)))


def ball_outline_rz_mm(r_mm: float, z_mm: float, diameter_mm: float, n: int = 96) -> np.ndarray:
    """(n + 1, 2) closed polyline (r, z) in mm: the circle of a ball of the given diameter about
    its centre in the r-z plane (first point repeated at the end)."""
    t = np.linspace(0.0, 2 * np.pi, n + 1)
    return np.column_stack([r_mm + 0.5 * diameter_mm * np.cos(t), z_mm + 0.5 * diameter_mm * np.sin(t)])


#: the percentile of a stress field's element values that sets the top of its colour range
COLOUR_PERCENTILE = 99.0


@dataclass(frozen=True)
class ColourRange:
    """Colour range of one field image: lo, hi (the field's unit); clipped: whether hi lies
    below the field's maximum (the values above it drawn in the top colour); max_value: the
    field's maximum."""
    lo: float
    hi: float
    clipped: bool
    max_value: float


def colour_range(values: np.ndarray, percentile: float | None = COLOUR_PERCENTILE,
                 weights: np.ndarray | None = None) -> ColourRange:
    """Colour range of a field: from its minimum to the `percentile`-th percentile of the values,
    each weighted by `weights` (the element areas of a stress field: a mesh graded towards a
    corner puts many small elements there, which must not count for more of the section than
    they cover). The few elements at a re-entrant corner, where the elastic stress is singular
    and grows without bound as the mesh is refined (Williams 1952), would otherwise set the whole
    scale and leave the section one colour. percentile None: the full range."""
    v = np.asarray(values, float)
    w = np.ones_like(v) if weights is None else np.asarray(weights, float)
    keep = np.isfinite(v)
    v, w = v[keep], w[keep]
    lo, top = float(v.min()), float(v.max())
    if percentile is None:
        hi = top
    else:
        order = np.argsort(v)
        cum = np.cumsum(w[order])
        k = int(np.searchsorted(cum, percentile / 100.0 * cum[-1]))
        hi = float(v[order][min(k, v.size - 1)])
    if hi <= lo:
        hi = top
    return ColourRange(lo, hi, hi < top, top)


def render_fields(out_dir: Path, stem: str, model: StackModel, u: np.ndarray,
                  cell_data: dict[str, np.ndarray], title: str,
                  T_vertex_C: np.ndarray | None = None, exaggeration: float | None = None,
                  balls_rz_d_mm: tuple[tuple[float, float, float], ...] = ()) -> list[Path]:
    """One PNG per field: temperature (if given), displacement magnitude on the deformed shape
    (the exaggeration factor is printed in the title), and every cell-data stress field. Each
    image names the parts on the section and carries a scale bar in mm under it. balls_rz_d_mm:
    (r, z, diameter) in mm of each bearing's ball, drawn as a circle at its nominal centre (the
    balls are analytic, not meshed)."""
    import pyvista as pv  # noqa: PLC0415 -- deferred: pyvista/VTK load only for images

    pv.OFF_SCREEN = True
    try:
        pv.vtk_verbosity("off")   # no "bad X server connection" chatter when rendering headless
    except AttributeError:
        pass
    out_dir.mkdir(parents=True, exist_ok=True)
    xy = model.mesh.p.T
    disp = vertex_values(model, u)
    umax = float(np.abs(disp).max()) or 1.0
    extent = float(np.ptp(xy, axis=0).max())
    if exaggeration is None:
        exaggeration = float(10 ** np.floor(np.log10(0.05 * extent / umax)))
    fields = []
    if T_vertex_C is not None:
        fields.append(("temperature_C", "point", T_vertex_C, "temperature (C)", xy))
    fields.append(("displacement_um", "point", 1e3 * np.linalg.norm(disp, axis=1),
                   "displacement (um)", xy + exaggeration * disp))
    for k, v in cell_data.items():
        fields.append((k, "cell", v, k.replace("_MPa", " (MPa)"), xy))
    p0, p1, p2 = (xy[model.mesh.t[k]] for k in range(3))
    a, b = p1 - p0, p2 - p0
    areas = 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])   # element areas, mm^2
    paths = []
    for name, kind, values, label, pts in fields:
        grid = _grid(model, pts)
        if kind == "point":
            grid.point_data[name] = values
        else:
            grid.cell_data[name] = values
        path = out_dir / f"{stem}_{name}.png"
        # VTK interrupted between making a render window and closing it crashed the interpreter
        # (a segmentation fault in 1 of 12 Ctrl-C trials): Ctrl-C and SIGTERM wait for the close
        with deferred_signals():
            p = pv.Plotter(off_screen=True, window_size=(800, 640))
            try:
                rng = (colour_range(values, COLOUR_PERCENTILE, areas) if kind == "cell"
                       else colour_range(values, None))
                _draw(p, grid, name, label, pts, model, title, exaggeration, balls_rz_d_mm, extent,
                      rng)
                p.screenshot(str(path))
            finally:
                p.close()
        paths.append(path)
    return paths


def _draw(p, grid, name: str, label: str, pts: np.ndarray, model: StackModel, title: str,
          exaggeration: float, balls_rz_d_mm, extent: float, rng: ColourRange) -> None:
    """Put one field of `render_fields` on the plotter `p`: the field in the colour range `rng`
    (a clipped range says so on its bar: "top = 99th percentile, max ..."), the outline, the
    balls, the part names, a scale bar (mm; `extent`: the undeformed section's size) and the
    title."""
    import pyvista as pv  # noqa: PLC0415 -- deferred: pyvista/VTK load only for images

    bar = (label if not rng.clipped else
           f"{label}\ntop: {COLOUR_PERCENTILE:g}th pct\nmax {rng.max_value:.3g}")
    p.add_mesh(grid, scalars=name, cmap="viridis", show_edges=False, clim=(rng.lo, rng.hi),
               scalar_bar_args={"title": bar, "vertical": True, "fmt": "%.3g",
                                "position_x": 0.78, "position_y": 0.15, "width": 0.06,
                                "height": 0.7, "title_font_size": 16, "label_font_size": 14})
    outline = _grid(model, pts).extract_feature_edges(boundary_edges=True, feature_edges=False,
                                                      manifold_edges=False)
    p.add_mesh(outline, color="black", line_width=1)
    for r, z, d in balls_rz_d_mm:
        ring = ball_outline_rz_mm(r, z, d)
        p.add_mesh(pv.lines_from_points(np.column_stack([ring, np.full(len(ring), 0.01 * extent)])),
                   color="black", line_width=2)
    where, names = part_label_points(model, pts)
    p.add_point_labels(np.column_stack([where, np.full(len(where), 0.01 * extent)]), names,
                       font_size=11, point_size=1, shape_opacity=0.6, always_visible=True,
                       show_points=False)
    ruler = scale_bar_mm(extent)
    x0, y0 = pts[:, 0].min(), pts[:, 1].min() - 0.06 * extent
    p.add_ruler([x0, y0, 0.0], [x0 + ruler, y0, 0.0], title=f"{ruler:g} mm", number_labels=2,
                show_labels=False, font_size_factor=0.8, label_size_factor=0.8)
    shape = f", deformed shape x{exaggeration:g}" if name == "displacement_um" else ""
    p.add_text(f"{title}: {label}{shape}", font_size=10)
    p.view_xy()
    p.add_axes(xlabel="r", ylabel="z", zlabel="")
