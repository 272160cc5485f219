"""A new assembly from Python, start to finish: model it, run the tolerance Monte Carlo, export its
stiffness to a rotor model (ROSS) and diagnose measured data, with plots.

    python docs/examples/new_assembly.py --out OUT [--quick]

Only `import bearingfem` is used (the functions are those of the command line, docs/cli.md
"Python API"). `--quick` runs it on the coarsest mesh the sizing rule allows (target error 1 %)
with few samples: the test suite runs it so (tests/test_examples.py). Everything written goes to
OUT: the assembly file, the tables, the plots (PNG) and the ROSS table.

The assembly: the shipped template pair (studies/configs/template.toml, two 7005-size angular
contact bearings back to back) changed into a titanium variant (TC4 shaft and housing, whose
expansion is close to the steel rings', as in seed 000) with a stiffer 150 N preload and
toleranced fits (k5 shaft seat, J6 housing bore).  The "measured"
data of the diagnosis are this model's own outputs with an as-built inner fit 2 um tighter than
drawn (the `interference_error` effect) plus noise: the diagnosis should name that cause or say
which look-alikes it cannot tell apart in this design.
"""
from __future__ import annotations

import argparse
import contextlib
import io
from pathlib import Path

import matplotlib

matplotlib.use("Agg")                                # files only, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import bearingfem  # noqa: E402

TEMPLATE = Path(__file__).resolve().parents[2] / "studies" / "configs" / "template.toml"


def new_assembly(out: Path, quick: bool) -> Path:
    """The template with a titanium shaft and housing, 150 N preload and ISO 286 fit classes, written to
    OUT/titanium_pair.toml (a TOML file is the assembly's one definition; every key and unit:
    the template's comments)."""
    text = TEMPLATE.read_text()
    edits = [('name = "my_pair"', 'name = "titanium_pair"'),
             ('[shaft]\nmaterial = "17-4PH"', '[shaft]\nmaterial = "TC4"'),
             ('[housing]\nmaterial = "6061"', '[housing]\nmaterial = "TC4"'),
             ("assembled_N = 100.0", "assembled_N = 150.0"),
             ('inner_shaft_class = ""  ', 'inner_shaft_class = "k5"'),
             ('outer_housing_class = ""  ', 'outer_housing_class = "J6"')]
    if quick:
        edits.append(("target_error = 0.001 ", "target_error = 0.01  "))
    for old, new in edits:
        assert old in text, f"template changed: {old!r} not found"
        text = text.replace(old, new, 1)
    path = out / "titanium_pair.toml"
    path.write_text(text)
    return path


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--quick", action="store_true", help="coarse mesh, few samples (the tests)")
    args = ap.parse_args(argv)
    out = args.out
    out.mkdir(parents=True, exist_ok=True)
    quick = args.quick

    # 1. model it: preload and torque over the operating range -----------------------------------
    asm = bearingfem.load_assembly(new_assembly(out, quick))
    T = np.linspace(-40.0, 80.0, 7 if quick else 25)
    sim = bearingfem.simulate(asm, {"T_ambient_C": T})
    fig, ax = plt.subplots(1, 2, figsize=(9, 3.5))
    ax[0].plot(T, sim["preload_N"], "o-")
    ax[0].set(xlabel="ambient temperature (C)", ylabel="preload (N)")
    ax[1].plot(T, sim["torque_Nmm"], "o-")
    ax[1].set(xlabel="ambient temperature (C)", ylabel="friction torque (N mm)")
    fig.tight_layout()
    fig.savefig(out / "preload_torque.png", dpi=100)
    plt.close(fig)
    print(f"preload {sim['preload_N'].min():.1f}..{sim['preload_N'].max():.1f} N over "
          f"{T[0]:g}..{T[-1]:g} C")

    # 2. tolerances: the fits drawn from their ISO 286 / ISO 492 bands ----------------------------
    tol = bearingfem.tolerance(asm, {"T_ambient_C": [-40.0, 20.0, 80.0]},
                               samples=8 if quick else 1000, seed=1, out=out / "tolerance")
    samples = tol.to_frame()
    fig, ax = plt.subplots(figsize=(5, 3.5))
    for t_c, rows in samples.groupby("T_ambient_C"):
        ax.hist(rows["preload_N"], bins=20, alpha=0.6, label=f"{t_c:g} C")
    ax.set(xlabel="preload (N)", ylabel="samples")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "preload_tolerance.png", dpi=100)
    plt.close(fig)
    print(f"tolerance: P(preload lost) {tol.preload_lost:.3g}; P(fit leaves its designed state) "
          + ", ".join(f"{f} {p:.3g}" for f, p in tol.fit_leaves_design.items()))

    # 3. stiffness into a rotor model (ROSS) ------------------------------------------------------
    speeds = np.linspace(0.0, 12000.0, 5)
    k = bearingfem.stiffness(asm, {"T_ambient_C": np.full(speeds.size, 20.0), "speed_rpm": speeds},
                             out=out / "stiffness.csv", ross=out / "ross_bearing.csv")
    table = k.ross.to_frame()                         # SI: frequency rad/s, k N/m, c N s/m
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            import ross                               # (prints CoolProp/REFPROP notices)
    except ImportError:
        print(f"ROSS is not installed (pip install 'bearingfem[ross]'): wrote its bearing table "
              f"to {out / 'ross_bearing.csv'} (ross.BearingElement(n=..., **columns) reads it)")
    else:
        bearing = ross.BearingElement(n=0, **{c: table[c].to_numpy() for c in table})
        kxx_rest = float(np.atleast_1d(bearing.kxx_interpolated(table["frequency"].iloc[0]))[0])
        print(f"ROSS BearingElement at node 0: kxx {kxx_rest:.4g} N/m at rest")
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot(speeds, k.to_frame()["k_xx_N_per_mm"], "o-", label="k_xx")
    ax.plot(speeds, k.to_frame()["k_zz_N_per_mm"], "s-", label="k_zz")
    ax.set(xlabel="speed (rpm)", ylabel="stiffness (N/mm)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "stiffness.png", dpi=100)
    plt.close(fig)

    # 4. a diagnosis of "measured" data -----------------------------------------------------------
    rng = np.random.default_rng(7)
    t_meas = np.linspace(-40.0, 80.0, 12 if quick else 40)
    truth = bearingfem.simulate(asm, {"T_ambient_C": t_meas},
                                effects={"interference_error": {"inner_um": 2.0}})
    measured = {"T_ambient_C": t_meas,
                "preload_N": truth["preload_N"] + rng.normal(0.0, 0.3, t_meas.size),
                "torque_Nmm": truth["torque_Nmm"] * (1.0 + rng.normal(0.0, 0.01, t_meas.size))}
    diag = bearingfem.diagnose(asm, measured, out=out / "diagnosis")
    print(f"diagnosis: {diag.verdict}" + (f" ({diag.cause})" if diag.cause else "")
          + f"; report in {out / 'diagnosis' / 'report.md'}")
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot(t_meas, measured["preload_N"], "k.", label="measured")
    ax.plot(T, sim["preload_N"], "-", label="model as drawn")
    ax.set(xlabel="ambient temperature (C)", ylabel="preload (N)", title=diag.verdict)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "diagnosis.png", dpi=100)
    plt.close(fig)


if __name__ == "__main__":
    main()
