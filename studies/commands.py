"""Implementations of `bearingfem simulate`, `study` and `diagnose` (argument parsing: cli.py)."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

from studies.cli import UserError, atomic_dir, progress

STUDIES = ("seed000", "seed001", "seed003", "mesh_convergence", "lubricant_viscosity")


def _load(assembly_path: Path):
    from studies.config import load_assembly

    return load_assembly(assembly_path)


def _user_errors():
    """Exception types that are the user's input problems (exit 2, one line)."""
    from fem.solver import SolveError
    from meshes.build import MeshError
    from studies.config import ConfigError
    from studies.diagnosis import DiagnosisError, ModelFailure
    from studies.effects import EffectError
    from studies.pipeline import ModelError
    from studies.table import TableError

    return (ConfigError, TableError, EffectError, MeshError, SolveError, ModelError,
            DiagnosisError, ModelFailure)


def check_output_file(path: Path) -> None:
    """Refuse an output path that cannot be written, before any work is done."""
    path = Path(path)
    if path.is_dir():
        raise UserError(f"{path}: is a folder; -o needs a file name")
    parent = path.resolve().parent
    probe = parent
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK):
        raise UserError(f"{path}: cannot write there ({probe} is not a writable folder)")


def simulate_table(asm, columns: dict, effects: dict | None = None, direct: bool = False,
                   pipeline=None) -> dict[str, np.ndarray]:
    """Model outputs for a conditions table (column arrays), effects switched on by name."""
    from studies.effects import apply_effects
    from studies.inputs import baseline_inputs
    from studies.pipeline import Pipeline

    n = len(next(iter(v for k, v in columns.items() if not k.startswith("_"))))
    inputs = baseline_inputs(columns, n, asm.T_ref_C, asm.preload.assembled_N,
                             asm.lubrication.speed_rpm)
    inputs = apply_effects(inputs, effects, asm.T_ref_C)
    pl = pipeline or Pipeline(asm, progress=progress)
    return pl.run(inputs, direct=direct)


def cmd_simulate(args) -> None:
    from studies.effects import parse_effect_arg
    from studies.table import read_conditions, write_table

    try:
        check_output_file(args.out)
        asm = _load(args.assembly)
        cond = read_conditions(args.conditions)
        effects = {}
        for text in args.effect:
            name, params = parse_effect_arg(text)
            if name in effects:
                raise UserError(f"--effect {name}: given twice")
            effects[name] = params
        out = simulate_table(asm, cond, effects, direct=args.direct)
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    cols = {k: v for k, v in cond.items() if not k.startswith("_")}
    cols.update(out)
    desc = ", ".join(f"{k}({', '.join(f'{p}={v:g}' for p, v in prm.items())})"
                     for k, prm in effects.items()) or "none"
    write_table(args.out, cols, comment=f"bearingfem simulate {args.assembly} {args.conditions}\n"
                                        f"effects: {desc}")
    print(f"wrote {len(next(iter(out.values())))} rows to {args.out}")


def cmd_study(args) -> None:
    if args.name not in STUDIES:
        raise UserError(f"study '{args.name}': unknown (known: {', '.join(STUDIES)})")
    import importlib

    mod = importlib.import_module(f"studies.study_{args.name}" if args.name != "lubricant_viscosity"
                                  else "studies.lubricant_viscosity")
    try:
        with atomic_dir(args.out) as tmp:
            mod.run(tmp) if args.name == "lubricant_viscosity" else mod.run(tmp, progress=progress)
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    print(f"study {args.name}: report in {args.out}/report.md")


def cmd_diagnose(args) -> None:
    from studies.diagnose_cli import diagnose_files

    try:
        with atomic_dir(args.out) as tmp:
            result = diagnose_files(args.assembly, args.measured, tmp, progress=progress)
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    print(f"diagnosis: {result['verdict']}" + (f" ({result['cause']})" if result.get("cause") else "")
          + f"; report in {args.out}/report.md", file=sys.stdout)
