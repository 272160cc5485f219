"""`bearingfem design`: search for an athermal stack, each candidate through the exact model.

Design variables (the assembly's own values are one candidate):
- the inner and outer spacer materials, from the material library (`analytic/materials.py`;
  materials with equal E, nu and CTE are one choice);
- the common spacer length, `LENGTH_FACTORS` x the assembly's;
- the clamp scheme of nut and cover (rigid or compliant faces), with `--clamps`;
- the assembled preload, `PRELOAD_FACTORS` x the assembly's (no new FE: one bearing run).

Every stack is its own FE model: the search screens all of them on a mesh twice as coarse
(`SCREEN_MESH_FACTOR`) and re-evaluates the best ones on the assembly's mesh (each through the
normal, cached FE set-up), so the ranking printed is the fine one. The screening's FE set-ups come
from `fem.parametric`: the stacks of one spacer length and clamp scheme (a family) share one
reference FE (mesh, assembly, factorisation, unit solutions, the spacers of the assembly's
materials), and a member's set-up follows from it exactly by condensing the two spacers and a
low-rank update (equal to the stack's own set-up to round-off, about 1e-12 relative: tests/
test_parametric.py); no stack is meshed or factorised on its own, only one stack per family.

Over the temperature range (uniform temperature, round steps) each candidate gets its preload range (max - min), its smallest preload, whether each fit
assembled with interference stays closed, its largest contact pressure against the limit
`simulate` checks, and its largest torque. Feasible: fits closed, preload kept, contact pressure
within the limit; `in_band`: the preload stays inside the band (x the assembled preload) at every
temperature. Ranked by the relative preload variation (range / assembled preload: the band is
relative too); the Pareto set is the feasible designs no other beats on all of relative preload
variation, largest torque and contact-pressure margin.

Why a design works: for the best design and the assembly as given, the preload change from the
reference temperature to each end of the range is split into the part the radial groove-centre
shifts cause (fits, ring growth) and the part the axial ones cause (stack lengths), with the same
pipeline run on the FE answer with only one set of shifts (as the seed 000 study does).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, replace
from functools import partial
from pathlib import Path

import numpy as np

from analytic.materials import MATERIALS, get_material
from fem.parametric import parametric_setup
from studies.model.checks import assembly_checks
from studies.model.inputs import baseline_inputs
from studies.model.memory import release_freed_memory
from studies.model.parallel import Blocks, map_blocks
from studies.model.pipeline import FEOptions, Pipeline
from studies.runs.report_tools import nice_step
from studies.runs.report_tools import line_plot, md_table, write_report_files

LENGTH_FACTORS = (0.5, 1.0, 1.5, 2.0)
PRELOAD_FACTORS = (0.5, 0.75, 1.0, 1.25, 1.5)
SCREEN_MESH_FACTOR = 2.0
N_TEMPERATURES = 15
CONFIRM = 5                      # best designs re-evaluated on the assembly's mesh
#: the parts whose material the search varies (the screening's FE set-up family, fem.parametric)
SPACERS = ("inner_spacer", "outer_spacer")


@dataclass(frozen=True)
class Stack:
    """The FE-relevant design variables of one candidate."""
    inner_spacer_material: str
    outer_spacer_material: str
    spacer_length_mm: float
    nut_clamp: str
    cover_clamp: str
    ring_section_delta_mm: float = 0.0   # effective ring sections thickened radially by this

    def assembly(self, asm):
        b, d = asm.bearing, self.ring_section_delta_mm
        return replace(asm, inner_spacer=replace(asm.inner_spacer, material=self.inner_spacer_material,
                                                 length_mm=self.spacer_length_mm),
                       outer_spacer=replace(asm.outer_spacer, material=self.outer_spacer_material,
                                            length_mm=self.spacer_length_mm),
                       nut=replace(asm.nut, clamp=self.nut_clamp),
                       cover=replace(asm.cover, clamp=self.cover_clamp),
                       bearing=replace(b, inner_ring_outer_diameter_mm=b.inner_ring_outer_diameter_mm + 2 * d,
                                       outer_ring_inner_diameter_mm=b.outer_ring_inner_diameter_mm - 2 * d))


def distinct_materials() -> list[str]:
    """One name per distinct (E, nu, CTE) in the library, the first listed."""
    seen, names = set(), []
    for name, m in MATERIALS.items():
        key = (m.E_MPa, m.nu, m.alpha_per_K)
        if key not in seen:
            seen.add(key)
            names.append(name)
    return names


#: every (nut, cover) clamp scheme
ALL_CLAMPS = tuple((n, c) for n in ("rigid", "compliant") for c in ("rigid", "compliant"))


def candidates(asm, clamps: bool = False, length_factors=LENGTH_FACTORS,
               materials=None, ring_deltas_mm=(0.0,)) -> list[Stack]:
    """The assembly as given first, then every combination of spacer materials (the library's
    distinct ones, or `materials`), common spacer length (x the given one), clamp scheme (with
    `clamps` all four, else the given one) and ring-section change (mm, radially)."""
    mats = materials or distinct_materials()
    L0 = asm.inner_spacer.length_mm
    schemes = ALL_CLAMPS if clamps else ((asm.nut.clamp, asm.cover.clamp),)
    out = [Stack(asm.inner_spacer.material, asm.outer_spacer.material, L0, asm.nut.clamp,
                 asm.cover.clamp)]
    for mi in mats:
        for mo in mats:
            for f in length_factors:
                for n, c in schemes:
                    for d in ring_deltas_mm:
                        s = Stack(mi, mo, round(f * L0, 6), n, c, float(d))
                        if s not in out:
                            out.append(s)
    return out


def parametric_setup_of(asm):
    """The screening's FE set-up route for the stacks of `asm`: `fem.parametric` with the spacers
    as the variable parts, their reference materials the assembly's own (fixed, so the numbers do
    not depend on which worker sees which stack first)."""
    ref = {p: get_material(getattr(asm, p).material, asm.materials) for p in SPACERS}
    return partial(parametric_setup, variable=SPACERS, reference=ref)


def _family_of(s: Stack) -> tuple:
    """What puts a stack in another FE family than its neighbours (all but the spacer
    materials)."""
    return (s.spacer_length_mm, s.nut_clamp, s.cover_clamp, s.ring_section_delta_mm)


def evaluate_stack(asm, stack: Stack, T_C: np.ndarray, preloads_N: np.ndarray,
                   mesh_factor: float, parametric: bool = False) -> dict:
    """Preload, contact pressure, fit pressures and torque of one stack at every temperature
    and preload: arrays (n_preloads, n_T). One task of the search. `parametric`: the FE set-up
    from the stack's family (`fem.parametric`, equal to the full set-up to round-off) instead of
    the stack's own (cached) one."""
    a = stack.assembly(asm)
    setup_of = parametric_setup_of(asm) if parametric and asm.fits.contact == "frictionless" else None
    pl = Pipeline(a, mesh_factor=mesh_factor, setup_of=setup_of)
    nT, nP = T_C.size, preloads_N.size
    cols = {"T_ambient_C": np.tile(T_C, nP), "preload_assembled_N": np.repeat(preloads_N, nT)}
    res = pl.run(baseline_inputs(cols, nT * nP, a.T_ref_C, a.preload.assembled_N,
                                 a.lubrication.speed_rpm))
    keep = {"preload_N": res.preload_N, "max_contact_pressure_MPa": res.max_contact_pressure_MPa,
            "fit_pressure_inner_MPa": res.fits.inner_MPa,
            "fit_pressure_outer_MPa": res.fits.outer_MPa, "torque_Nmm": res.torque_Nmm}
    out = {k: v.reshape(nP, nT) for k, v in keep.items()} | {"dofs": pl.ndofs}
    del pl, res
    release_freed_memory()      # one FE after another fragments the C heap (studies/model/memory.py)
    return out


def _metrics(asm, r: dict, preloads_N, band) -> list[dict]:
    limit = next(c.allowable for c in assembly_checks(asm) if c.name == "max_contact_pressure_MPa")
    fi, fo = asm.mean_fits_um()
    out = []
    for k, P0 in enumerate(preloads_N):
        P = r["preload_N"][k]
        lo, hi = band[0] * P0, band[1] * P0
        closed = ((fi <= 0 or r["fit_pressure_inner_MPa"][k].min() > 0)
                  and (fo <= 0 or r["fit_pressure_outer_MPa"][k].min() > 0))
        p_max = float(r["max_contact_pressure_MPa"][k].max())
        m = {"preload_assembled_N": float(P0), "preload_range_N": float(np.ptp(P)),
             "preload_variation": float(np.ptp(P) / P0),
             "preload_min_N": float(P.min()), "preload_max_N": float(P.max()),
             "fits_closed": bool(closed), "max_contact_pressure_MPa": p_max,
             "contact_pressure_margin": float(limit / p_max - 1) if p_max > 0 else float("inf"),
             "torque_max_Nmm": float(r["torque_Nmm"][k].max())}
        m["feasible"] = bool(closed and P.min() > 0 and p_max <= limit)
        m["in_band"] = bool(m["feasible"] and P.min() >= lo and P.max() <= hi)
        out.append(m)
    return out


def rank_key(d):
    """Sort key: feasible first, then the smaller relative preload variation."""
    return (not d["feasible"], d["preload_variation"])


def pareto(designs: list[dict]) -> list[dict]:
    """Feasible designs that no other feasible design beats on all of relative preload variation
    (lower), largest torque (lower) and contact-pressure margin (higher)."""
    feas = [d for d in designs if d["feasible"]]

    def key(d):
        return np.array([d["preload_variation"], d["torque_max_Nmm"], -d["contact_pressure_margin"]])
    front = []
    for d in feas:
        kd = key(d)
        if not any(np.all(key(e) <= kd) and np.any(key(e) < kd) for e in feas if e is not d):
            front.append(d)
    return sorted(front, key=lambda d: d["preload_variation"])


def run(asm, T_min_C: float, T_max_C: float, out: Path, provenance: dict, band=(0.8, 1.2),
        clamps: bool = False, progress=print, workers: int | None = None,
        scheduler: str | None = None, screen_mesh_factor: float = SCREEN_MESH_FACTOR,
        confirm_mesh_factor: float = 1.0, length_factors=LENGTH_FACTORS,
        materials: list[str] | None = None, bar=None) -> dict:
    """Search, write design.json, plots and the report into `out`; returns design.json.
    `bar(done, total)` follows the stacks (the command line's progress bar)."""
    step = nice_step(T_max_C - T_min_C, N_TEMPERATURES)
    T = np.unique(np.concatenate([[T_min_C, T_max_C, asm.T_ref_C],
                                  step * np.arange(np.ceil(T_min_C / step), np.floor(T_max_C / step) + 1)]))
    T = T[(T >= T_min_C) & (T <= T_max_C)]
    P0 = asm.preload.assembled_N * np.array(PRELOAD_FACTORS)
    stacks = candidates(asm, clamps, length_factors, materials)
    progress(f"design: {len(stacks)} stacks x {P0.size} preloads x {T.size} temperatures "
             f"(screening mesh x{screen_mesh_factor:g}) ...")
    with Blocks(workers, scheduler) as where:      # one cluster for screening and confirm
        # submitted family by family (spacer length, clamps, ring sections): a worker then
        # builds few of the families (fem.parametric); the results go back to the stacks' order
        order = sorted(range(len(stacks)), key=lambda i: _family_of(stacks[i]))
        done = map_blocks(evaluate_stack, [(asm, stacks[i], T, P0, screen_mesh_factor, True)
                                           for i in order],
                          where=where,
                          progress=bar or (lambda d, n: progress(f"  stack {d} of {n}")
                                           if d % 20 == 0 or d == n else None))
        screened = [None] * len(stacks)
        for i, r in zip(order, done):
            screened[i] = r
        designs = []
        for i, (s, r) in enumerate(zip(stacks, screened)):
            for m in _metrics(s.assembly(asm), r, P0, band):
                designs.append({"stack": i, **s.__dict__, **m, "is_given": i == 0,
                                "mesh": "screen"})
        # confirm the best feasible ones (and the assembly as given) on the fine mesh
        ranked = sorted(designs, key=rank_key)
        best_stacks = list(dict.fromkeys([0] + [d["stack"] for d in ranked
                                                if d["feasible"]][:CONFIRM]))
        progress(f"design: confirming {len(best_stacks)} stacks on the assembly's mesh ...")
        fine = map_blocks(evaluate_stack, [(asm, stacks[i], T, P0, confirm_mesh_factor)
                                           for i in best_stacks], where=where)
    confirmed = []
    for i, r in zip(best_stacks, fine):
        for m in _metrics(stacks[i].assembly(asm), r, P0, band):
            confirmed.append({"stack": i, **stacks[i].__dict__, **m, "is_given": i == 0, "mesh": "fine"})
    confirmed.sort(key=rank_key)
    given = next(d for d in confirmed if d["is_given"]
                 and d["preload_assembled_N"] == asm.preload.assembled_N)
    best = next((d for d in confirmed if d["feasible"]), None)
    why = _why(asm, stacks, best, T) if best is not None else None
    result = {"range_C": [T_min_C, T_max_C], "temperatures_C": [float(t) for t in T],
              "band": list(band), "n_stacks": len(stacks), "n_designs": len(designs),
              "given": given, "designs": confirmed, "screened": sorted(
                  designs, key=rank_key),
              "pareto": pareto(designs), "why": why, "provenance": provenance}
    (out / "design.json").write_text(json.dumps(result, indent=1, default=float) + "\n")
    _report(asm, out, result, stacks, T, P0, fine, best_stacks)
    return result


def _why(asm, stacks, best, T) -> dict:
    """Preload change (end of range minus reference) split into radial- and axial-shift parts,
    for the assembly as given and the best design, at the best design's assembled preload."""
    out = {}
    for label, i in (("given", 0), ("best", best["stack"])):
        a = stacks[i].assembly(asm)
        pl = Pipeline(a)
        Ts = np.array([T[0], a.T_ref_C, T[-1]])
        inp = baseline_inputs({"T_ambient_C": Ts}, 3, a.T_ref_C, best["preload_assembled_N"],
                              a.lubrication.speed_rpm)
        res = pl.run(inp)
        fe, ref = res.fe, res.fe_ref
        full = res.preload_N
        radial = pl.run(inp, fe_options=FEOptions(shifts="radial_only")).preload_N
        axial = pl.run(inp, fe_options=FEOptions(shifts="axial_only")).preload_N
        out[label] = {"T_C": [float(t) for t in Ts],
                      "change_N": [float(full[k] - full[1]) for k in (0, 2)],
                      "radial_shifts_only_N": [float(radial[k] - full[1]) for k in (0, 2)],
                      "axial_shifts_only_N": [float(axial[k] - full[1]) for k in (0, 2)],
                      "dz_A_um": [float(1e3 * (fe.dz_mm[0, k] - ref.dz_mm[0, k])) for k in (0, 2)],
                      "dr_A_um": [float(1e3 * (fe.dr_mm[0, k] - ref.dr_mm[0, k])) for k in (0, 2)]}
    return out


def _label(d) -> str:
    return (f"spacers {d['inner_spacer_material']}/{d['outer_spacer_material']} "
            f"{d['spacer_length_mm']:g} mm, clamps {d['nut_clamp']}/{d['cover_clamp']}, "
            f"{d['preload_assembled_N']:g} N")


def _report(asm, out, res, stacks, T, P0, fine, best_stacks):
    k0 = int(np.argmin(np.abs(P0 - asm.preload.assembled_N)))
    series = {}
    for i, r in zip(best_stacks, fine):
        s = stacks[i]
        lab = ("as given" if i == 0 else f"{s.inner_spacer_material}/{s.outer_spacer_material} "
               f"{s.spacer_length_mm:g} mm")
        series[lab] = r["preload_N"][k0]
    line_plot(out / "preload_vs_temperature.png", T, series, "temperature (C)", "preload (N)",
              f"Preload over the range, assembled {P0[k0]:g} N (fine mesh)", markers=True)
    _scatter(out / "pareto.png", res)
    g, rows = res["given"], []
    for d in res["designs"][:10]:
        rows.append([_label(d), d["preload_variation"], d["preload_range_N"], d["preload_min_N"],
                     d["preload_max_N"], "yes" if d["fits_closed"] else "NO",
                     d["contact_pressure_margin"], d["torque_max_Nmm"],
                     "yes" if d["feasible"] else "no", "yes" if d["in_band"] else "no"])
    lines = [f"# Athermal stack search: {asm.name}", "",
             f"bearingfem {res['provenance']['version']}; range {res['range_C'][0]:g}..{res['range_C'][1]:g} C "
             f"({len(T)} temperatures), preload band {res['band'][0]:g}..{res['band'][1]:g} x the "
             f"assembled preload; {res['n_stacks']} stacks x {len(P0)} assembled preloads = "
             f"{res['n_designs']} designs, each stack its own FE model (screened on a coarser mesh, "
             "the best re-evaluated on the assembly's mesh: the numbers below).", "",
             f"As given: {_label(g)}: preload range {g['preload_range_N']:.1f} N over the range "
             f"({g['preload_min_N']:.1f}..{g['preload_max_N']:.1f} N, "
             f"{100 * g['preload_variation']:.0f} % of the assembled preload).", "",
             "## Best designs (fine mesh)", "",
             md_table(["design", "range / assembled", "preload range (N)", "min (N)", "max (N)",
                       "fits closed", "contact-pressure margin", "max torque (N mm)", "feasible",
                       "in band"], rows), "",
             "![preload](preload_vs_temperature.png)", "",
             "## Pareto set (screening mesh)", "",
             "Feasible designs that no other beats on relative preload variation, largest torque and "
             "contact-pressure margin at once.", "",
             md_table(["design", "range / assembled", "max torque (N mm)", "contact-pressure margin"],
                      [[_label(d), d["preload_variation"], d["torque_max_Nmm"],
                        d["contact_pressure_margin"]] for d in res["pareto"][:15]]), "",
             "![pareto](pareto.png)", ""]
    w = res["why"]
    if w is not None:
        b = res["designs"][0]
        lines += ["## Why the best design works", "",
                  md_table(["stack", "end", "preload change (N)", "radial shifts only (N)",
                            "axial shifts only (N)", "dz A change (um)", "dr A change (um)"],
                           [[lab, f"{w[lab]['T_C'][2 * e]:g} C", w[lab]["change_N"][e],
                             w[lab]["radial_shifts_only_N"][e], w[lab]["axial_shifts_only_N"][e],
                             w[lab]["dz_A_um"][e], w[lab]["dr_A_um"][e]]
                            for lab in ("given", "best") for e in (0, 1)]), "",
                  _explain(w, b), ""]
    write_report_files(out, lines, f"Athermal stack search: {asm.name}")


def _explain(w, best) -> str:
    """The decomposition in words, end by end, from the numbers (nothing assumed)."""
    g, b = w["given"], w["best"]
    parts = []
    for e, end in ((0, "cold"), (1, "hot")):
        r, a, t = b["radial_shifts_only_N"][e], b["axial_shifts_only_N"][e], b["change_N"][e]
        how = "against" if r * a < 0 else "with"
        parts.append(f"at the {end} end ({b['T_C'][2 * e]:g} C) the axial shifts act {how} the "
                     f"radial ones ({a:+.1f} N vs {r:+.1f} N; as given {g['axial_shifts_only_N'][e]:+.1f} "
                     f"vs {g['radial_shifts_only_N'][e]:+.1f} N), total {t:+.1f} N (as given "
                     f"{g['change_N'][e]:+.1f} N)")
    return (f"With {best['inner_spacer_material']} inner and {best['outer_spacer_material']} outer "
            f"spacers of {best['spacer_length_mm']:g} mm the spacers' axial growth difference "
            "changes the axial groove-centre shifts, while the radial ones (fits, ring growth) stay "
            "almost as they were: " + "; ".join(parts) + ". The radial part is not linear in "
            "temperature (a fit tightens or opens), the axial part nearly is, so a spacer choice "
            "can balance the two only on average over the range.")


def _scatter(path, res):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    d = res["screened"]
    feas = [x for x in d if x["feasible"]]
    inf = [x for x in d if not x["feasible"]]
    ax.scatter([x["preload_variation"] for x in inf], [x["torque_max_Nmm"] for x in inf], s=6,
               c="lightgrey", label="infeasible")
    ax.scatter([x["preload_variation"] for x in feas], [x["torque_max_Nmm"] for x in feas], s=8,
               c="tab:blue", label="feasible")
    p = res["pareto"]
    ax.scatter([x["preload_variation"] for x in p], [x["torque_max_Nmm"] for x in p], s=18,
               c="tab:red", label="Pareto set")
    ax.set_xlabel("preload range over the temperature range / assembled preload")
    ax.set_ylabel("largest friction torque (N mm)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax.set_title("Designs: preload stability vs torque", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
