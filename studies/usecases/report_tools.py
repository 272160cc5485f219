"""Small helpers shared by the studies: plots (matplotlib, Agg), markdown tables, field images."""
from __future__ import annotations

import base64
import re
from pathlib import Path

import numpy as np


def line_plot(path: Path, x, series: dict, xlabel: str, ylabel: str, title: str = "",
              markers: bool = False, vlines: dict | None = None) -> Path:
    """One PNG with several labelled curves sharing an x axis."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for label, y in series.items():
        xs, ys = (y if isinstance(y, tuple) else (x, y))
        ax.plot(xs, ys, "o-" if markers else "-", ms=3, label=label)
    for label, xv in (vlines or {}).items():
        ax.axvline(xv, color="grey", ls="--", lw=0.8)
        ax.text(xv, ax.get_ylim()[1], f" {label}", va="top", fontsize=7, color="grey")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    if len(series) > 1:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def md_table(header: list[str], rows: list[list], digits: int = 4) -> str:
    def fmt(v):
        if isinstance(v, float):
            return f"{v:.{digits}g}"
        return str(v)
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(fmt(v) for v in r) + " |" for r in rows]
    return "\n".join(out)


#: relative size below which a printed value is round-off of its column (the FE and the
#: bearing solve carry ~1e-12 of the largest term; a table prints 4 digits)
ROUND_OFF = 1e-9


def significant(column, i: int) -> float:
    """Value i of a result column for printing: 0 where it is round-off of the column's scale
    (e.g. a fit pressure of 4e-10 MPa in a column that reaches 10 MPa)."""
    col = np.asarray(column, float)
    v = float(col[i])
    scale = float(np.max(np.abs(col[np.isfinite(col)]), initial=0.0))
    return 0.0 if abs(v) <= ROUND_OFF * scale else v


#: the stresses drawn as images (the VTU carries every component)
IMAGE_STRESSES = ("sigma_hoop_MPa", "von_mises_MPa")


def field_images(out_dir: Path, pipeline, T_C: float, stem: str, title: str) -> list[Path]:
    """VTU (displacement, temperature, every stress component) and PNG images (displacement on
    the deformed shape, hoop and von Mises stress) of the stack at a uniform temperature with the
    nominal fits."""
    from fem.fields import render_fields, write_vtu
    from fem.post import element_stresses, theta_per_element
    from studies.model.inputs import baseline_inputs

    a = pipeline.asm
    inp = baseline_inputs({"T_ambient_C": np.array([T_C])}, 1, a.T_ref_C, a.preload.assembled_N,
                          a.lubrication.speed_rpm)
    f = pipeline.field(inp)
    u, model = f.u_mm, pipeline.model
    stresses = element_stresses(model, u, theta_per_element(model, f.theta))
    T_vertex = np.full(model.mesh.p.shape[1], T_C)
    write_vtu(out_dir / f"{stem}.vtu", model, u, stresses, T_vertex)
    from studies.model.stack import ball_centres_rz_mm

    balls = tuple((r, z, a.bearing.ball_diameter_mm) for r, z in ball_centres_rz_mm(a))
    return render_fields(out_dir, stem, model, u, {k: stresses[k] for k in IMAGE_STRESSES}, title,
                         balls_rz_d_mm=balls)


def safety_section(asm, result, film_parameter=None, title: str = "over the study's operating points") -> str:
    """Markdown table of the checks `simulate` applies (studies/model/checks.py) at the governing
    operating point of each (`result.checks` of a `SimulationResult`), plus the EHL film
    parameter for oil (analytic/safety.py)."""
    from analytic.safety import film_parameter_flag

    n = result.n_rows
    rows = []
    for o in result.checks.outcomes:
        c, v = o.check, o.value
        i = int(np.argmax(v) if c.upper else np.argmin(v))
        bad = int(o.violated.sum())
        rel = "<=" if c.upper else (">" if c.strict else ">=")
        rows.append([c.name, f"{significant(v, i):.4g} {c.unit}".strip(), f"{rel} {c.allowable:g}",
                     "ok" if bad == 0 else f"NO ({bad} of {n})",
                     "" if o.margin is None else f"{o.margin[i]:+.3f}", f"row {i + 1}", c.source])
    if film_parameter is not None and asm.lubrication.kind == "oil":
        f = film_parameter_flag(film_parameter)
        rows.append([f.name, f"{f.value:.4g}", f">= {f.limit:g}", "ok" if f.ok else "NO", "",
                     "" if f.worst_index is None else f"row {f.worst_index + 1}",
                     "GB/T 28878.2 Annex B.1"])
    return "\n".join([f"## Safety checks ({title})", "",
                      md_table(["check", "governing value", "allowable", "ok", "margin",
                                "governing point", "allowable from"], rows), ""])


def write_report_files(out: Path, lines: list[str], title: str) -> None:
    """`report.md` from markdown lines and a self-contained `report.html` beside it (the
    markdown rendered, every PNG it links embedded)."""
    import markdown

    md = "\n".join(lines) + "\n"
    (out / "report.md").write_text(md)
    body = markdown.markdown(md, extensions=["tables"])

    def embed(m):
        path = out / m.group(1)
        if not path.is_file():
            return m.group(0)
        data = base64.b64encode(path.read_bytes()).decode("ascii")
        return f'src="data:image/png;base64,{data}"'
    body = re.sub(r'src="([^"]+\.png)"', embed, body)
    style = ("body{font-family:sans-serif;max-width:1100px;margin:2em auto;line-height:1.4}"
             "table{border-collapse:collapse;font-size:0.85em}td,th{border:1px solid #bbb;"
             "padding:2px 6px}table{display:block;overflow-x:auto;max-width:100%}"
             "img{max-width:48%;margin:2px;vertical-align:top}")
    (out / "report.html").write_text(
        f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{title}</title>"
        f"<style>{style}</style></head><body>{body}</body></html>\n")


def nice_step(span: float, n: int) -> float:
    """The smallest 1, 2 or 5 x 10^k step that divides `span` into at most n - 1 intervals."""
    raw = span / max(n - 1, 1)
    k = 10.0 ** np.floor(np.log10(raw)) if raw > 0 else 1.0
    return float(next(m * k for m in (1, 2, 5, 10) if m * k >= raw * (1 - 1e-12)))
