"""The `bearingfem` command line (contract: shared/spec/cli.md).

Bad input exits 2 with one line on stderr naming the file, row or column and the problem; no
traceback and no partial output (results are written to a temporary folder/file and renamed).
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # small dense solves: threads only cost here

import argparse  # noqa: E402
import shutil  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from contextlib import contextmanager  # noqa: E402
from pathlib import Path  # noqa: E402


class UserError(Exception):
    """Bad input: printed as one line, exit code 2."""


def progress(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


MARKER = ".bearingfem-output"


@contextmanager
def atomic_dir(out: Path):
    """Yield a temporary folder beside `out`; move it to `out` only when the block succeeds.

    An existing `out` is replaced only if it is empty or was written by bearingfem (it holds the
    marker file); any other existing folder is refused, so nothing the user keeps there is lost.
    On failure the previous content stays untouched and the temporary folder is removed."""
    out = Path(out).resolve()
    if out.exists():
        if not out.is_dir():
            raise UserError(f"{out}: exists and is not a folder")
        if any(out.iterdir()) and not (out / MARKER).exists():
            raise UserError(f"{out}: folder exists and was not written by bearingfem; choose a new "
                            "or empty folder (nothing was changed)")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    except OSError as exc:
        raise UserError(f"{out}: cannot create the output folder ({exc.strerror})") from None
    tmp.chmod(0o755)
    (tmp / MARKER).write_text("written by bearingfem; this folder is replaced by the next run\n")
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    if out.exists():
        old = out.with_name(f".{out.name}.old")
        shutil.rmtree(old, ignore_errors=True)
        out.rename(old)
        tmp.rename(out)
        shutil.rmtree(old, ignore_errors=True)
    else:
        tmp.rename(out)


def cmd_verify(args) -> None:
    from studies import verify

    with atomic_dir(args.out) as tmp:
        cases = verify.run(tmp, progress=progress)
    bad = [c["name"] for c in cases if c["kind"] in ("lame_fit", "lame_displacement", "free_thermal")
           and c["rel_error"] > verify.TOLERANCE]
    print(f"verification: {len(cases)} cases written to {args.out}/verification.md"
          + (f"; OUTSIDE tolerance: {', '.join(bad)}" if bad else "; all Lamé cases within 0.5 %"))


def cmd_bench(args) -> None:
    from studies import bench

    bench.main(quick=args.quick)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="bearingfem", description=(
        "Thermal-structural FE + analytic bearing model of a preloaded angular-contact ball "
        "bearing pair on a shaft in a housing."))
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    s = sub.add_parser("simulate", help="run the model on a conditions table")
    s.add_argument("assembly", type=Path)
    s.add_argument("conditions", type=Path)
    s.add_argument("-o", "--out", type=Path, required=True)
    s.add_argument("--effect", action="append", default=[], metavar="NAME:key=value[,key=value]")
    s.add_argument("--direct", action="store_true",
                   help="direct FE solve per row instead of superposed unit solutions")

    d = sub.add_parser("diagnose", help="find what the model gets wrong in measured data")
    d.add_argument("assembly", type=Path)
    d.add_argument("measured", type=Path)
    d.add_argument("--out", type=Path, required=True)

    v = sub.add_parser("verify", help="FE against closed forms, mesh convergence")
    v.add_argument("--out", type=Path, required=True)
    v.set_defaults(func=cmd_verify)

    st = sub.add_parser("study", help="run a named study (seed000, seed001, seed003, "
                                      "mesh_convergence, lubricant_viscosity)")
    st.add_argument("name")
    st.add_argument("--out", type=Path, required=True)

    b = sub.add_parser("bench", help="print FE and analytic timings on this machine")
    b.add_argument("--quick", action="store_true", help="fewer mesh levels")
    b.set_defaults(func=cmd_bench)
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    from studies.config import ConfigError

    try:
        func = getattr(args, "func", None)
        if func is None:
            from studies import commands

            func = getattr(commands, f"cmd_{args.command}")
        func(args)
    except (UserError, ConfigError) as exc:
        print(f"bearingfem {args.command}: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("bearingfem: interrupted", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main())
