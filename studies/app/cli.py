"""The `bearingfem` command line (contract: docs/cli.md).

Bad input exits 2 with one line on stderr naming the file, row or column and the problem; no
traceback and no partial output (results are written to a temporary folder/file and renamed).
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # small dense solves: threads only cost here

import argparse  # noqa: E402
import signal  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

from infra.version import __version__  # noqa: E402
from studies.app import commands  # noqa: E402
from studies.app.output import UserError  # noqa: E402
from studies.usecases import defaults  # noqa: E402
from studies.validation import STUDIES  # noqa: E402


class Terminated(BaseException):
    """SIGTERM (timeout, batch schedulers, docker stop): unwinds like Ctrl-C, so every temporary
    file and folder is removed on the way out."""


class _Parser(argparse.ArgumentParser):
    """Usage errors as one line on stderr (exit 2), like every other bad input."""

    def error(self, message):
        self.exit(2, f"{self.prog}: {message} (see {self.prog.split()[0]} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="bearingfem", description=(
        "Thermal-structural FE + analytic bearing model of a preloaded angular-contact ball "
        "bearing pair on a shaft in a housing."))
    p.add_argument("--version", action="version", version=f"bearingfem {__version__}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=_Parser)

    s = sub.add_parser("simulate", help="run the model on a conditions table")
    s.add_argument("assembly", type=Path)
    s.add_argument("conditions", type=Path)
    s.add_argument("-o", "--out", type=Path, required=True)
    s.add_argument("--effect", action="append", default=[], metavar="NAME:key=value[,key=value]")
    s.add_argument("--direct", action="store_true",
                   help="direct FE solve per row instead of superposed unit solutions")
    s.add_argument("--strict", action="store_true",
                   help="exit 1 when a row violates a limit (flag_* columns; summary on stderr)")
    swhere = s.add_mutually_exclusive_group()
    swhere.add_argument("--workers", type=int, default=None,
                        help="evaluate the row chunks on N worker processes")
    swhere.add_argument("--scheduler", default=None,
                        help="evaluate them on an existing Dask cluster (tcp://host:port)")

    d = sub.add_parser("diagnose", help="find what the model gets wrong in measured data")
    d.add_argument("assembly", type=Path)
    d.add_argument("measured", type=Path)
    d.add_argument("--out", type=Path, required=True)
    d.add_argument("--noise", action="append", default=[], metavar="COLUMN=REL%[+ABS]",
                   help="a sensor's standard uncertainty, e.g. torque_Nmm=1.5%%+0.2 (1.5 %% of "
                        "reading plus 0.2 N mm) or preload_N=0.5 (may repeat); the rows' weights, "
                        "the level still checked against the data")

    v = sub.add_parser("verify", help="FE against closed forms, mesh convergence")
    v.add_argument("--out", type=Path, required=True)
    v.add_argument("--assembly", type=Path, default=None,
                   help="also the mesh convergence (observed order, GCI) of this assembly's stack")

    r = sub.add_parser("report", help="the engineer's report for any assembly")
    r.add_argument("assembly", type=Path)
    r.add_argument("conditions", type=Path, nargs="?", default=None,
                   help="conditions table (default: the assembly's operating temperature range)")
    r.add_argument("--out", type=Path, required=True)
    r.add_argument("--pdf", action="store_true", help="also report.pdf (typst, no LaTeX)")
    r.add_argument("--sensitivity", action="store_true",
                   help="also the ring section and the [assume]-tagged numbers in "
                        "\"Assumptions that decide the answer\", and sensitivity.csv")

    bb = sub.add_parser("bearing", help="one bearing under radial, axial and moment loads")
    bb.add_argument("bearing", type=Path, help="TOML file with a [bearing] table")
    bb.add_argument("loads", type=Path, help="loads table (CSV)")
    bb.add_argument("-o", "--out", type=Path, required=True)
    bb.add_argument("--convention", choices=("exact", "iso16281"),
                    default=defaults.BEARING_CONVENTION,
                    help="exact groove-centre geometry (default) or the ISO/TS 16281 "
                         "simplifications")
    bb.add_argument("--control", choices=("outer", "inner", "jones"),
                    default=defaults.BEARING_CONTROL,
                    help="raceway control of the quasi-dynamic balls (rows with speed_rpm): "
                         "outer (default), inner, or jones (Jones's criterion per ball)")

    sf = sub.add_parser("stiffness", help="the pair's tangent stiffness matrix at its "
                                          "equilibrium per row (rotordynamics; ROSS table)")
    sf.add_argument("assembly", type=Path)
    sf.add_argument("conditions", type=Path)
    sf.add_argument("-o", "--out", type=Path, required=True)
    sf.add_argument("--per-bearing", action="store_true",
                    help="also each bearing's matrix about its own ball plane (suffix _A, _B)")
    sf.add_argument("--ross", type=Path, default=None, metavar="OUT.csv",
                    help="also the coefficients against speed in the table layout ROSS reads")
    sf.add_argument("--free-axial", action="store_true",
                    help="also the force-controlled radial stiffness k_xx_condensed_N_per_mm "
                         "(axial load and moment held: axial position and tilt free)")

    t = sub.add_parser("tolerance", help="worst case and Monte Carlo of the fit tolerances")
    t.add_argument("assembly", type=Path)
    t.add_argument("conditions", type=Path, nargs="?", default=None,
                   help="conditions table (default: the assembly's operating temperature range)")
    t.add_argument("--samples", type=int, default=defaults.TOLERANCE_SAMPLES,
                   help=f"Monte Carlo samples (default {defaults.TOLERANCE_SAMPLES})")
    t.add_argument("--seed", type=int, default=defaults.TOLERANCE_SEED,
                   help=f"random seed (default {defaults.TOLERANCE_SEED})")
    t.add_argument("--out", type=Path, required=True)
    where = t.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=None,
                       help="run the Monte Carlo on N worker processes")
    where.add_argument("--scheduler", default=None,
                       help="run it on an existing Dask cluster (tcp://host:port)")

    dz = sub.add_parser("design", help="search spacer materials, lengths, clamps and preload "
                                       "for an athermal stack")
    dz.add_argument("assembly", type=Path)
    dz.add_argument("--range", required=True, metavar="T_MIN:T_MAX",
                    help="temperature range in C, e.g. -60:80")
    dz.add_argument("--band", default=None, metavar="LOW:HIGH",
                    help="preload band as fractions of the assembled preload (default "
                         f"{defaults.DESIGN_BAND[0]:g}:{defaults.DESIGN_BAND[1]:g})")
    dz.add_argument("--band-N", dest="band_N", default=None, metavar="LOW:HIGH",
                    help="instead: the preload band in N, e.g. 44.5:445")
    dz.add_argument("--vary", action="append", default=[], metavar="KEY=V1,V2,...",
                    help="also vary a setting (may repeat): preload_kind, spring_rate_N_per_mm, "
                         "contact_angle_free_deg, inner_shaft_class, outer_housing_class")
    dz.add_argument("--clamps", action="store_true",
                    help="also try rigid and compliant nut and cover faces")
    dz.add_argument("--out", type=Path, required=True)
    dwhere = dz.add_mutually_exclusive_group()
    dwhere.add_argument("--workers", type=int, default=None,
                        help="evaluate the stacks on N worker processes")
    dwhere.add_argument("--scheduler", default=None,
                        help="evaluate them on an existing Dask cluster (tcp://host:port)")

    st = sub.add_parser("study", help=f"run a named study ({', '.join(STUDIES)})")
    st.add_argument("name")
    st.add_argument("--out", type=Path, required=True)

    b = sub.add_parser("bench", help="print FE and analytic timings on this machine")
    b.add_argument("--quick", action="store_true", help="fewer mesh levels")
    b.add_argument("--tolerance", type=int, metavar="N", default=None,
                   help="instead: Monte Carlo throughput with N samples, here, on 1 and on 2 worker "
                        "processes (wall, CPU, load)")
    b.add_argument("--design", action="store_true",
                   help="instead: the design search of seed 000 (324 stacks), cold and warm FE "
                        "cache (wall, CPU, load), and the workers' memory per stack")
    b.add_argument("--workers", type=int, default=None,
                   help="with --tolerance: only on N workers; with --design: N workers "
                        "(default 2, 0 = this process)")
    b.add_argument("--simulate", action="store_true",
                   help="instead: whole-process simulate times (3 rows, cold and warm cache) per "
                        "assembly, DOF, and peak memory for 1e5 and 1e6 rows (--quick: 1e4, 1e5)")
    b.add_argument("--diagnose", action="store_true",
                   help="instead: time of a 500-row diagnosis with all candidates (seed000), per "
                        "phase in model calls and in the engine")
    b.add_argument("--rows", type=int, nargs="+", default=None, metavar="N",
                   help="with --diagnose: the rows per dataset kind (several: one run each; "
                        "default 500)")
    b.add_argument("--datasets", nargs="+", default=None, metavar="PART",
                   help="with --diagnose: only the dataset kinds whose label contains one of "
                        "these (e.g. thermal_transient_fe)")
    b.add_argument("--fresh", action="store_true",
                   help="with --diagnose: also each kind's whole diagnose in a new process (what "
                        "a user's command costs: imports, set-ups read from the cache)")
    b.add_argument("--cold", action="store_true",
                   help="with --diagnose --fresh: that process on an empty cache folder (every "
                        "mesh and FE set-up built, as on a first run)")
    b.add_argument("--transient", action="store_true",
                   help="instead: seed 003's 30-minute heat-up (900 steps of 2 s): reduction, "
                        "reduced and full-FE transient times, preload error reduced vs full")
    b.add_argument("--friction", action="store_true",
                   help="instead: the speed exponent of the friction torque of an oil-jet "
                        "angular-contact bearing at high speed, per friction model, with its data")
    b.add_argument("--assembly", type=Path, action="append", default=[],
                   help="with --simulate: one more assembly to time (may repeat)")
    return p


#: the one dispatch table: subcommand -> implementation (studies/app/commands.py)
COMMANDS = {"simulate": commands.cmd_simulate, "report": commands.cmd_report,
            "bearing": commands.cmd_bearing, "stiffness": commands.cmd_stiffness,
            "tolerance": commands.cmd_tolerance, "design": commands.cmd_design,
            "diagnose": commands.cmd_diagnose,
            "verify": commands.cmd_verify, "study": commands.cmd_study, "bench": commands.cmd_bench}


def _terminate(signum, frame):
    raise Terminated()


#: options whose value may start with a minus sign (a temperature range such as -60:80), which
#: argparse would otherwise take for an option
SIGNED_VALUE_OPTIONS = ("--range", "--band")


def _join_signed_values(argv: list[str]) -> list[str]:
    out, i = [], 0
    while i < len(argv):
        if argv[i] in SIGNED_VALUE_OPTIONS and i + 1 < len(argv) and argv[i + 1].startswith("-"):
            out.append(f"{argv[i]}={argv[i + 1]}")
            i += 2
        else:
            out.append(argv[i])
            i += 1
    return out


def main(argv=None) -> int:
    """Run one command; the exit code. Ctrl-C at any point, the start-up included, is one line
    ("bearingfem: interrupted") and exit code 130, SIGTERM one line and 143."""
    try:
        return _main(argv)
    except KeyboardInterrupt:
        print("bearingfem: interrupted", file=sys.stderr)
        return 130
    except ImportError as exc:
        if isinstance(exc.__context__, KeyboardInterrupt):   # Ctrl-C inside a lazy import
            print("bearingfem: interrupted", file=sys.stderr)
            return 130
        raise


def _main(argv) -> int:
    argv = _join_signed_values(list(sys.argv[1:] if argv is None else argv))
    args = build_parser().parse_args(argv)
    # deferred (numpy, the model's config): the start-up before them is short, and Ctrl-C while
    # they load is caught by `main`
    import numpy as np  # noqa: PLC0415

    from studies.model.config import ConfigError  # noqa: PLC0415

    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        with np.errstate(all="ignore"):       # non-finite results are reported by row instead
            code = COMMANDS[args.command](args) or 0
    except (UserError, ConfigError) as exc:
        print(f"bearingfem {args.command}: {exc}", file=sys.stderr)
        return 2
    except Terminated:
        print("bearingfem: terminated", file=sys.stderr)
        return 143
    finally:
        signal.signal(signal.SIGTERM, previous)
    return code


if __name__ == "__main__":
    sys.exit(main())
