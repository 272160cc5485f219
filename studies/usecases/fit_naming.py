"""The fits of an assembly and the names the tool gives them, drawn on the assembly's own r-z
section: which part is `[sleeve]` and which `[cartridge]`, and which `[fits]` keys set and
tolerance each fit.

The tool's `[sleeve]` is the *inner* layer (the outer rings sit in it) and `[cartridge]` the
*outer* one (it sits in the housing): the opposite of the common usage where a cartridge holds
the bearings and a sleeve lines the housing. The names are kept (existing assembly files keep
working); this picture, in docs/ and in every report of an assembly with a layer, says which is
which. Each fit is named after the part *inside* it: `outer_*` the outer rings in whatever they sit
in, `sleeve_*` the sleeve in whatever it sits in, `cartridge_*` the cartridge in the housing.

    python -m studies.usecases.fit_naming [ASSEMBLY.toml] -o docs/fit_naming.png

draws an assembly (default: `example_assembly`, the template with a sleeve and a cartridge).
"""
from __future__ import annotations

import argparse
from pathlib import Path

#: colours of the parts (the rest grey)
COLOURS = {"shaft": "#9fb7cf", "inner_ring_A": "#d9a35f", "inner_ring_B": "#d9a35f",
           "outer_ring_A": "#d9a35f", "outer_ring_B": "#d9a35f", "sleeve": "#7fc97f",
           "cartridge": "#beaed4", "housing": "#bdbdbd", "cover": "#d4d4d4",
           "inner_spacer": "#e8d9b5", "outer_spacer": "#e8d9b5", "nut": "#c9d6e3"}
#: what each fit is called in `[fits]`: (interference key, tolerance keys of the inside member,
#: of the bore)
FIT_KEYS = {"inner": ("inner_interference_um", "inner_shaft_*", "inner_ring_bore_*"),
            "outer": ("outer_interference_um", "outer_ring_od_*", "outer_housing_*"),
            "sleeve": ("sleeve_interference_um", "sleeve_shaft_*", "sleeve_bore_*"),
            "cartridge": ("cartridge_interference_um", "cartridge_shaft_*", "cartridge_bore_*")}


def example_assembly():
    """The template pair with a 2 mm 17-4PH `[sleeve]` (inner layer) and a 3 mm TC4
    `[cartridge]` (outer layer) in its housing: the picture in docs/."""
    import tomllib

    from studies.model.config import CONFIG_DIR, assembly_from_dict

    raw = tomllib.loads((CONFIG_DIR / "template.toml").read_text())
    b = raw["bearing"]
    length = 2 * b["width_mm"] + raw["outer_spacer"]["length_mm"]
    raw["sleeve"] = {"material": "17-4PH", "radial_thickness_mm": 2.0, "length_mm": length}
    raw["cartridge"] = {"material": "TC4", "radial_thickness_mm": 3.0, "length_mm": length}
    raw["housing"]["bore_diameter_mm"] = b["outside_diameter_mm"] + 10.0
    raw["assembly"]["name"] = "template with a sleeve and a cartridge"
    return assembly_from_dict(raw)


def draw(asm, path: Path) -> Path:
    """PNG of the upper half of the assembly's r-z section (the section the FE meshes,
    `studies.model.stack.section_from_assembly`): parts coloured and named with their config
    table, each fit line marked with its `[fits]` keys."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    from studies.model.stack import section_from_assembly

    sec = section_from_assembly(asm)
    fig, ax = plt.subplots(figsize=(10.0, 6.0))
    for rc in sec.rects:
        ax.add_patch(Rectangle((rc.z0_mm, rc.r0_mm), rc.z1_mm - rc.z0_mm, rc.r1_mm - rc.r0_mm,
                               facecolor=COLOURS.get(rc.part, "#dddddd"), edgecolor="black",
                               linewidth=0.6))
    z_lo = min(rc.z0_mm for rc in sec.rects)
    z_hi = max(rc.z1_mm for rc in sec.rects)
    r_hi = max(rc.r1_mm for rc in sec.rects)
    width = z_hi - z_lo
    layers = dict(asm.layers())
    labels = {"shaft": "[shaft]", "housing": "[housing]", "outer_ring_A": "outer ring A",
              "inner_ring_A": "inner ring A"}
    for part, text in labels.items():
        rc = max((rc for rc in sec.rects if rc.part == part),
                 key=lambda r: (r.z1_mm - r.z0_mm) * (r.r1_mm - r.r0_mm))
        ax.text(0.5 * (rc.z0_mm + rc.z1_mm), 0.5 * (rc.r0_mm + rc.r1_mm), text, fontsize=8,
                ha="center", va="center")
    # the layers named on the right, the fits on the left, labels spread over the height
    names = {"sleeve": "[sleeve] = the INNER layer\n(the outer rings sit in it)",
             "cartridge": "[cartridge] = the OUTER layer\n(it sits in the housing)"}
    for k, name in enumerate(reversed(list(layers))):
        rc = next(rc for rc in sec.rects if rc.part == name)
        ax.annotate(names[name], xy=(0.5 * (rc.z0_mm + rc.z1_mm), 0.5 * (rc.r0_mm + rc.r1_mm)),
                    xytext=(0.70, 0.80 - 0.22 * k), textcoords="axes fraction", fontsize=9,
                    fontweight="bold", ha="left", va="center",
                    arrowprops=dict(arrowstyle="->", lw=0.8))
    fits = {}
    for f in sec.fits:
        fits.setdefault(f.key, []).append(f)
    order = sorted(fits, key=lambda key: -fits[key][0].r_mm)       # from the outside in
    for k, key in enumerate(order):
        for f in fits[key]:
            ax.plot([f.z0_mm, f.z1_mm], [f.r_mm, f.r_mm], color="red", lw=2.0)
        f = fits[key][0]
        name, shaft, bore = FIT_KEYS[key]
        ax.annotate(f"{key} fit: {name}\ntolerances {shaft} / {bore}",
                    xy=(f.z0_mm, f.r_mm), xytext=(0.01, 0.92 - 0.8 * k / max(len(order) - 1, 1)),
                    textcoords="axes fraction", fontsize=8, color="darkred", ha="left",
                    va="center", arrowprops=dict(arrowstyle="->", color="darkred", lw=0.7))
    ax.set_xlim(z_lo - 1.1 * width, z_hi + 1.1 * width)
    ax.set_ylim(0.0, 1.08 * r_hi)
    ax.set_xlabel("z (mm)")
    ax.set_ylabel("r (mm)")
    ax.set_title(f"Fits and their names: {asm.name} (r-z section, upper half; red: fits)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return Path(path)


def report_lines(asm, out: Path) -> list[str]:
    """Markdown subsection "Which layer is which" with the picture (`fit_naming.png` in `out`);
    nothing for an assembly without a sleeve or cartridge."""
    if not asm.layers():
        return []
    p = draw(asm, out / "fit_naming.png")
    return ["## Fits and their names", "",
            "In this tool `[sleeve]` is the inner layer (the outer rings sit in it) and "
            "`[cartridge]` the outer one (it sits in the housing), the opposite of the common "
            "usage; each fit is named after the part inside it (`sleeve_*`: the sleeve in what "
            "holds it). The fits of this assembly on its own section:", "",
            f"![fit naming]({p.name})", ""]


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("assembly", nargs="?", help="assembly TOML (default: the example)")
    ap.add_argument("-o", "--out", default="docs/fit_naming.png")
    args = ap.parse_args(argv)
    if args.assembly:
        from studies.model.config import load_assembly

        asm = load_assembly(args.assembly)
    else:
        asm = example_assembly()
    print(draw(asm, Path(args.out)))


if __name__ == "__main__":
    main()
