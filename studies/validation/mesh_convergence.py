"""Study `mesh_convergence`: the FE quantities that feed the bearing model over mesh levels.

For the shipped seed 000 stack at -60 C and 80 C: mean fit pressures, the inner-minus-outer
groove-centre shifts of bearing A (radial and axial) and the resulting preload, over five mesh
levels (element sizes halved each time, direct FE solves with exact contact). Observed order and
grid convergence index per quantity (Roache 1998, Fs = 1.25, three finest levels).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from studies.model.config import load_shipped
from studies.model.inputs import baseline_inputs
from studies.model.columns import to_columns
from studies.model.pipeline import Pipeline
from studies.usecases.report_tools import md_table
from studies.model.table import write_table
from studies.usecases.verify import ConvergenceLevel, convergence_case, plot_convergence

FACTORS = (4.0, 2.0, 1.0, 0.5, 0.25)
T_STATES_C = (-60.0, 80.0)
#: the quantities per level (columns of `to_columns`), the outer fit dropped where it is open
QUANTITIES = ("fit_pressure_inner_A_MPa", "fit_pressure_outer_A_MPa", "groove_shift_dr_A_um",
              "groove_shift_dz_A_um", "preload_N")
OUTER_FIT = QUANTITIES[1]


def run(out: Path, progress=print) -> None:
    asm = load_shipped("seed000")
    levels = {T: [] for T in T_STATES_C}
    for fac in FACTORS:
        pl = Pipeline(asm, mesh_factor=fac, superpose=False)
        progress(f"mesh_convergence: level x{fac:g}, {pl.ndofs} DOF ...")
        T = np.array(T_STATES_C)
        inp = baseline_inputs({"T_ambient_C": T}, T.size, asm.T_ref_C, asm.preload.assembled_N,
                              asm.lubrication.speed_rpm)
        res = to_columns(pl.run(inp, direct=True), flags=False)     # the levels' table by name
        for i, Tc in enumerate(T_STATES_C):
            levels[Tc].append(ConvergenceLevel(
                fac, pl.section.size_mm, pl.section.fit_size_mm, int(pl.ndofs),
                {q: float(res[q][i]) for q in QUANTITIES}))
    cases = []
    for Tc in T_STATES_C:
        rows = levels[Tc]
        if all(r.values[OUTER_FIT] == 0 for r in rows):
            for r in rows:
                del r.values[OUTER_FIT]        # open fit: nothing to converge
        c = convergence_case(f"seed000 at {Tc:g} C", dict(assembly=asm.name, T_C=Tc), rows)
        cases.append(c)
        table = [r.to_json() for r in rows]
        write_table(out / f"levels_{Tc:+.0f}C.csv", {k: np.array([r[k] for r in table])
                                                   for k in table[0]})
    plot_convergence(out / "mesh_convergence.png", cases)
    lines = ["# Study mesh_convergence: seed 000 stack", "",
             "Direct FE solves with exact contact on five meshes (sizes halved each level); the "
             "preload uses the pair model on each level's groove-centre shifts. Observed order p and "
             "GCI from the three finest levels (Roache 1998, Fs = 1.25).", ""]
    for c in cases:
        qs = list(c.quantities)
        x1 = c.levels[FACTORS.index(1.0)].values
        lines += [f"## {c.name}", "", md_table(["DOF", "fit size (mm)"] + qs,
                  [[lv.dofs, lv.fit_size_mm] + [lv.values[q] for q in qs] for lv in c.levels], digits=8), "",
                  md_table(["quantity", "observed order", "Richardson value", "GCI fine", "default mesh (x1) rel. error"],
                           [[q, r.richardson.observed_order, r.richardson.extrapolated,
                             f"{r.richardson.gci_fine:.2e}",
                             f"{abs(x1[q] - r.richardson.extrapolated) / abs(r.richardson.extrapolated):.2e}"]
                            for q, r in c.quantities.items()]), ""]
    lines += ["The ends of each fit and the clamped ring corners are stress singularities, so the "
              "orders are lower than the 2-4 of P2 on smooth problems (see `bearingfem verify` for "
              "the smooth Lamé case); the default mesh (x1) is within the tabulated error of the "
              "extrapolated values, far below what the bearing model is sensitive to.", "",
              "![convergence](mesh_convergence.png)", ""]
    (out / "report.md").write_text("\n".join(lines) + "\n")
