"""The commands' implementations (argument parsing: cli.py): each but `study` and `bench` turns
its flags into a call of its use case (`studies.usecases.api`, the call the Python API makes) and
prints the result, its warning lines (`api.warning_lines`) on stderr.

Each command imports the model it needs inside its function, on purpose: the command line starts
(and `--help`, `--version` and usage errors answer) without loading numpy, scipy, scikit-fem,
gmsh, pyvista or Dask, and Ctrl-C while they load is caught by `cli.main` (one line, exit 130).
None of these deferred imports hides a cycle (tests/test_imports.py counts them as edges).
"""
from __future__ import annotations

import sys

from studies.app.output import UserError, atomic_dir, progress, progress_bar
from studies.usecases import defaults
from studies.validation import STUDIES, study_module


def _user_errors():
    """Exception types that are the user's input problems (exit 2, one line)."""
    from fem.solver import SolveError
    from meshes.build import MeshError
    from studies.model.config import ConfigError
    from studies.diagnosis.core import DiagnosisError, ModelFailure
    from studies.model.effects import EffectError
    from studies.model.pipeline import ModelError
    from studies.model.table import TableError
    from studies.model.parallel import SchedulerError
    from studies.usecases.bearing_single import BearingRunError
    from studies.usecases.design_search import DesignError
    from studies.usecases.output_folder import OutputError
    from studies.usecases.stiffness import StiffnessRunError
    from studies.usecases.tolerance_report import ToleranceError

    return (ConfigError, TableError, EffectError, MeshError, SolveError, ModelError,
            DiagnosisError, ModelFailure, ToleranceError, SchedulerError, OutputError,
            DesignError, StiffnessRunError, BearingRunError)


def cmd_simulate(args) -> None:
    from studies.model.effects import parse_effect_arg
    from studies.usecases import api

    if args.workers is not None and args.workers < 1:
        raise UserError(f"--workers {args.workers}: need at least 1")
    effects = {}
    try:
        for text in args.effect:
            name, params = parse_effect_arg(text)
            if name in effects:
                raise UserError(f"--effect {name}: given twice")
            effects[name] = params
        run = api.simulate(args.assembly, args.conditions, effects, args.out, direct=args.direct,
                           workers=args.workers, scheduler=args.scheduler, progress=progress)
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    _warn("simulate", run)
    print(f"wrote {run.n_rows} rows to {args.out}")
    return 1 if run.violations and args.strict else 0


def _warn(command: str, result) -> None:
    """The result's warning lines (`api.warning_lines`) on stderr, one each."""
    from studies.usecases.api import warning_lines

    for line in warning_lines(result):
        print(f"bearingfem {command}: warning: {line}", file=sys.stderr)


def cmd_bearing(args) -> None:
    from studies.usecases import api

    try:
        res = api.bearing(args.bearing, args.loads, args.out, args.convention, args.control)
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    _warn("bearing", res)
    print(f"wrote {res.n_rows} rows to {args.out} (convention {args.convention}, "
          f"{args.control} control)")


def cmd_stiffness(args) -> None:
    from studies.usecases import api

    try:
        res = api.stiffness(args.assembly, args.conditions, args.out, args.per_bearing, args.ross,
                            progress=progress, free_axial=args.free_axial)
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    _warn("stiffness", res)
    print(f"wrote {res.n_rows} rows to {args.out}")
    if res.ross is not None:
        print(f"wrote the ROSS table ({res.ross.speeds_rpm.size} speeds, "
              f"{res.ross.range_text}; ROSS extrapolates outside) to {args.ross}")


def cmd_report(args) -> None:
    from studies.usecases import api

    command = ["bearingfem", "report", str(args.assembly)] + \
        ([str(args.conditions)] if args.conditions is not None else []) + \
        ["--out", str(args.out)] + (["--pdf"] if args.pdf else []) + \
        (["--sensitivity"] if args.sensitivity else [])
    try:
        res = api.report(args.assembly, args.conditions, args.out, pdf=args.pdf,
                         progress=progress, command=command, sensitivity=args.sensitivity)
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    _warn("report", res)
    print(f"report: {args.out}/report.md, report.html" + (" and report.pdf" if args.pdf else "")
          + (", sensitivity.csv" if args.sensitivity else ""))


def cmd_tolerance(args) -> None:
    from studies.usecases import api

    if args.samples < 2:
        raise UserError(f"--samples {args.samples}: need at least 2")
    if args.workers is not None and args.workers < 1:
        raise UserError(f"--workers {args.workers}: need at least 1")
    try:
        res = api.tolerance(args.assembly, args.conditions, samples=args.samples, seed=args.seed,
                            out=args.out, workers=args.workers, scheduler=args.scheduler,
                            progress=progress, bar=progress_bar("Monte Carlo"))
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    _warn("tolerance", res)
    fits = ", ".join(f"{f} {p:.3g}" for f, p in res.fit_leaves_design.items())
    print(f"tolerance: {res.samples} samples; P(fit leaves its designed state) {fits}, "
          f"P(preload lost) {res.preload_lost:.3g}; report in {args.out}/report.md")


def _pair(text: str, flag: str) -> tuple[float, float]:
    """'A:B' -> (A, B) with A < B, or a one-line UserError naming the flag."""
    try:
        lo, hi = (float(v) for v in text.split(":"))
    except ValueError:
        raise UserError(f"{flag} {text}: expected LOW:HIGH, two numbers") from None
    if not lo < hi:
        raise UserError(f"{flag} {text}: LOW must be below HIGH")
    return lo, hi


def _vary(items: list[str]) -> dict[str, tuple]:
    """`--vary KEY=V1,V2,...` (repeatable) -> {key: values}, each value parsed as the key's type
    (`design_search.SETTING_KEYS`); one-line UserError naming the flag otherwise."""
    from studies.usecases.design_search import SETTING_KEYS

    out: dict[str, tuple] = {}
    for item in items:
        key, eq, text = item.partition("=")
        key = key.strip()
        if not eq or not text.strip():
            raise UserError(f"--vary {item}: expected KEY=V1,V2,... (keys: {', '.join(SETTING_KEYS)})")
        if key not in SETTING_KEYS:
            raise UserError(f"--vary {key}: unknown (known: {', '.join(SETTING_KEYS)})")
        if key in out:
            raise UserError(f"--vary {key}: given twice")
        try:
            out[key] = tuple(SETTING_KEYS[key](v.strip()) for v in text.split(","))
        except ValueError:
            raise UserError(f"--vary {item}: {key} takes numbers") from None
    return out


def cmd_design(args) -> None:
    from studies.usecases import api

    T_min, T_max = _pair(args.range, "--range")
    if args.band is not None and args.band_N is not None:
        raise UserError("--band and --band-N: give one (fractions of the assembled preload, or N)")
    band_N = None
    if args.band_N is not None:
        band_N = _pair(args.band_N, "--band-N")
        if band_N[0] < 0:
            raise UserError(f"--band-N {args.band_N}: LOW must be at least 0 N")
    band = defaults.DESIGN_BAND if args.band is None else _pair(args.band, "--band")
    vary = _vary(args.vary)
    if not (-150.0 <= T_min and T_max <= 300.0):
        raise UserError(f"--range {args.range}: outside -150..300 C (range of the material data)")
    if args.workers is not None and args.workers < 1:
        raise UserError(f"--workers {args.workers}: need at least 1")
    try:
        res = api.design(args.assembly, (T_min, T_max), args.out, band=band, band_N=band_N,
                         clamps=args.clamps, vary=vary, workers=args.workers,
                         scheduler=args.scheduler, progress=progress,
                         bar=progress_bar("stacks", "stack"))
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    _warn("design", res)
    g, b = res.given.metrics, res.designs[0].metrics
    print(f"design: {res.n_designs} designs; as given {100 * g.preload_variation:.0f} % preload "
          f"variation, best {100 * b.preload_variation:.0f} %; report in {args.out}/report.md")
    if not res.pareto:                   # nothing feasible: say which constraint failed
        from studies.usecases.design_search import infeasible_text

        print(f"design: {infeasible_text(res.why)}")


def cmd_study(args) -> None:
    if args.name not in STUDIES:
        raise UserError(f"study '{args.name}': unknown (known: {', '.join(STUDIES)})")
    mod = study_module(args.name)
    try:
        with atomic_dir(args.out) as tmp:
            mod.run(tmp, progress=progress)
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    print(f"study {args.name}: report in {args.out}/report.md")


def cmd_diagnose(args) -> None:
    from studies.diagnosis.noisemodel import parse_noise_arg
    from studies.usecases import api

    try:
        noise = dict(parse_noise_arg(a) for a in args.noise)
        result = api.diagnose(args.assembly, args.measured, args.out, progress=progress,
                              noise=noise)
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    _warn("diagnose", result)
    print(f"diagnosis: {result.verdict}" + (f" ({result.cause})" if result.cause else "")
          + f"; report in {args.out}/report.md", file=sys.stdout)


def cmd_verify(args) -> None:
    from studies.usecases import api, verify

    try:
        result = api.verify(args.out, args.assembly, progress=progress)
    except _user_errors() as exc:
        raise UserError(str(exc)) from None
    bad = [c.name for c in result.cases if c.kind in ("lame_fit", "lame_multilayer", "lame_displacement",
                                                           "free_thermal")
           and c.rel_error > verify.TOLERANCE] + [m.name for m in (*result.mms, *result.mms_transient)
                                                   if not m.passed]
    print(f"verification: {len(result.cases) + len(result.convergence)} cases and "
          f"{len(result.mms) + len(result.mms_transient)} manufactured-solution orders written to "
          f"{args.out}/verification.md"
          + (f"; OUTSIDE tolerance: {', '.join(bad)}" if bad
             else "; all Lamé cases within 0.5 %, all orders as expected"))


def cmd_bench(args) -> None:
    if args.friction:
        from studies.bench import bench_friction

        bench_friction.main()
        return
    if args.transient:
        from studies.bench.bench_transient import main as bench_transient

        bench_transient([])
        return
    if args.diagnose:
        from studies.bench import bench_diagnose

        if args.cold and not args.fresh:
            raise UserError("--cold: only with --fresh")
        bench_diagnose.main((["--rows", *map(str, args.rows)] if args.rows else [])
                            + (["--datasets", *args.datasets] if args.datasets else [])
                            + (["--fresh"] if args.fresh else [])
                            + (["--cold"] if args.cold else []))
        return
    if args.rows or args.datasets or args.fresh or args.cold:
        raise UserError("--rows, --datasets, --fresh, --cold: only with --diagnose")
    if args.simulate:
        from studies.bench import bench_simulate

        missing = [a for a in args.assembly if not a.is_file()]
        if missing:
            raise UserError(f"{missing[0]}: file not found")
        bench_simulate.main(quick=args.quick, assemblies=tuple(args.assembly))
        return
    if args.workers is not None and (args.workers < 0 or (args.workers == 0 and not args.design)):
        raise UserError(f"--workers {args.workers}: need at least 1 (0 only with --design)")
    if args.workers is not None and args.tolerance is None and not args.design:
        raise UserError("--workers: only with --tolerance or --design")
    if args.tolerance is not None:
        from studies.bench import bench_tolerance

        if args.tolerance < 1:
            raise UserError(f"--tolerance {args.tolerance}: need at least 1 sample")
        bench_tolerance.main(args.tolerance, args.workers)
        return
    if args.design:
        from studies.bench import bench_design

        bench_design.main(2 if args.workers is None else args.workers)
        return
    from studies.bench import bench

    bench.main(quick=args.quick)
