"""`bearingfem bench`: timings on this machine, printed (never asserted by a test).

Per mesh level of the seed 000 stack: DOFs, gmsh time, assembly time, factorisation and one
solve; the unit-solution set-up; an 11-point vs a 1401-point uniform-temperature sweep through
the superposition; the time of a converged solve (fit pressure within 0.1 % of the Richardson
value) from a cold mesh cache.
"""
from __future__ import annotations

import time

import numpy as np


def _t(f, *a, **k):
    t0 = time.perf_counter()
    out = f(*a, **k)
    return out, time.perf_counter() - t0


def fe_levels(asm, factors, T_C=-60.0):
    from fem.model import StackModel
    from fem.post import fit_mean_pressures
    from fem.solver import FitSolver
    from meshes.build import build_mesh, read_section_mesh
    from studies.model.stack import section_from_assembly

    base = section_from_assembly(asm)
    rows = []
    print(f"{'factor':>6} {'DOF':>7} {'mesh s':>7} {'asm s':>7} {'factor s':>8} {'solve s':>8} "
          f"{'p_inner_A MPa':>14}")
    for fac in factors:
        sec = base.scaled(fac)
        path, t_mesh = _t(build_mesh, sec, refresh=True)
        model, t_asm = _t(lambda: StackModel(sec, read_section_mesh(path), asm.fits.contact))
        solver = FitSolver(model)
        theta = np.array([model.materials[p].thermal_strain(T_C, asm.T_ref_C) for p in model.part_names])
        delta = np.array([asm.mean_fits_um()[0 if f.key == "inner" else 1] / 2000 for f in model.fits])
        sol = solver.solve(model.unit_loads @ theta, delta)
        closed = sol.closed
        solver.clear_cache()
        _, t_fac = _t(solver.factorize, closed)
        _, t_sol = _t(solver.solve_status, closed, model.unit_loads @ theta, delta)
        p = fit_mean_pressures(model, solver.fit_of_pair, sol.force_N)[0, 0]
        print(f"{fac:6.2f} {model.ndofs:7d} {t_mesh:7.3f} {t_asm:7.3f} {t_fac:8.3f} {t_sol:8.4f} {p:14.8f}")
        rows.append((fac, model.ndofs, p, t_mesh + t_asm + t_fac + t_sol))
    return rows


def sweep(asm):
    from fem.model import build_model
    from fem.solver import FitSolver, Superposition
    from studies.model.stack import section_from_assembly

    sec = section_from_assembly(asm)
    model = build_model(sec, asm.fits.contact)
    probe = model.probe_matrix(np.array(list(sec.raceway_points.values())).T)
    sup, t_units = _t(Superposition, FitSolver(model), probe)
    print(f"unit solutions ({model.ndofs} DOF, {sup.ps.size} contact pairs): {t_units:.3f} s once")
    delta = np.array([asm.mean_fits_um()[0 if f.key == "inner" else 1] / 2000 for f in model.fits])
    for n in (11, 1401):
        T = np.linspace(-60, 80, n)
        theta = np.array([[model.materials[p].thermal_strain(t, asm.T_ref_C) for p in model.part_names]
                          for t in T])
        sup.clear_cache()
        res, t = _t(sup.evaluate, theta, np.tile(delta, (n, 1)))
        print(f"{n:5d}-point sweep -60..80 C: {t:.4f} s ({1e3 * t / n:.3f} ms/point, "
              f"{len(res.closed_sets)} distinct contact active sets)")


def pipeline_sweep(asm):
    """The whole chain (FE superposition + pair equilibrium + Hertz + torque) per sweep point."""
    from studies.model.inputs import baseline_inputs
    from studies.model.pipeline import Pipeline

    pl, t_build = _t(Pipeline, asm, cache=False)
    print(f"pipeline set-up (mesh from cache, assembly, unit solutions, compliance; not the "
          f"cached FE set-up, see bench --simulate): {t_build:.3f} s once")
    for n in (11, 1401):
        T = np.linspace(-60, 80, n)
        inp = baseline_inputs({"T_ambient_C": T}, n, asm.T_ref_C, asm.preload.assembled_N,
                              asm.lubrication.speed_rpm)
        pl.sup.clear_cache()
        _, t = _t(pl.run, inp)
        print(f"{n:5d}-point pipeline sweep: {t:.4f} s ({1e3 * t / n:.3f} ms/point)")


def main(quick: bool = False) -> None:
    from studies.model.config import load_shipped

    asm = load_shipped("seed000")
    print("== FE per mesh level (seed 000 stack, -60 C, direct solve with exact contact) ==")
    rows = fe_levels(asm, (4.0, 2.0, 1.0) if quick else (4.0, 2.0, 1.0, 0.5, 0.25))
    from studies.usecases.verify import richardson

    ext = richardson([r[2] for r in rows]).extrapolated
    conv = [r for r in rows if abs(r[2] - ext) / abs(ext) < 1e-3]
    if conv:
        fac, dofs, p, t = conv[0]
        print(f"converged solve (p within 0.1 % of Richardson {ext:.6f} MPa): factor {fac}, {dofs} DOF, "
              f"{t:.3f} s for mesh + assembly + factorisation + solve")
    print("== superposition sweeps (default mesh) ==")
    sweep(asm)
    print("== full pipeline sweeps (default mesh) ==")
    pipeline_sweep(asm)
    try:
        from studies.bench import bench_analytic
    except ImportError:
        return
    print("== analytic pair model ==")
    bench_analytic.main([])
