"""`radial_load_N` and `moment_Nmm` as condition columns of `simulate` (docs/cli.md): the rows
reach the pair with the shaft free to tilt over the stack's bearing span; rows without radial load
and moment keep the axial-only answer exactly; the reactions balance the applied loads (statics);
bad values are one line and exit 2 with no output."""
import numpy as np
import pytest

import bearingfem
from studies.app.cli import main
from studies.model.config import CONFIG_DIR, load_assembly
from studies.model.pipeline import Pipeline
from studies.model.stack import stack_positions

CFG = CONFIG_DIR / "seed000_71807C_TC4.toml"


def test_radial_load_and_moment_rows():
    """Seed 000 stack at 20 and 50 C.  (a) Rows with zero radial load and moment: every output
    column bit-identical to the same table simulated without the two columns (the axial-only
    route; same rows, so the same FE batch), radial displacement and tilt zero, reactions zero to
    round-off.  (b) Loaded rows: the two reactions
    add up to the radial load (force balance, 1e-9 of the load); a pure moment gives equal and
    opposite reactions; reversing the moment reverses tilt and reactions (the stack is mirror
    symmetric at a uniform temperature up to the groove shifts, so to 1e-3); a radial load
    leaves the rotor displaced towards it.  (c) The span the pipeline uses is the distance of
    the inner-ring mid-planes of the stack."""
    asm = load_assembly(CFG)
    T = [20.0, 50.0, 20.0, 20.0, 20.0, 50.0]
    Fr = [0.0, 0.0, 300.0, 0.0, 0.0, 800.0]
    M = [0.0, 0.0, 0.0, 4000.0, -4000.0, 2500.0]
    out = bearingfem.simulate(asm, {"T_ambient_C": T, "radial_load_N": Fr, "moment_Nmm": M})
    base = bearingfem.simulate(asm, {"T_ambient_C": T})
    for k, v in base.items():
        if k not in ("radial_force_A_N", "radial_force_B_N"):
            assert np.array_equal(out[k][:2], v[:2], equal_nan=True), k   # NaN: not stated
    assert np.all(out["radial_displacement_um"][:2] == 0.0) and np.all(out["tilt_mrad"][:2] == 0.0)
    for k in ("radial_force_A_N", "radial_force_B_N"):    # sum of 24 ball forces: round-off
        assert np.all(np.abs(out[k][:2]) <= 1e-12 * 24 * out["ball_load_A_N"][:2]), k
    assert np.array_equal(np.maximum(out["max_contact_pressure_A_MPa"], out["max_contact_pressure_B_MPa"]),
                          out["max_contact_pressure_MPa"])
    FA, FB = out["radial_force_A_N"], out["radial_force_B_N"]
    np.testing.assert_allclose(FA + FB, Fr, rtol=0, atol=1e-9 * 800.0)
    assert out["radial_displacement_um"][2] > 0 and out["tilt_mrad"][3] > 0
    np.testing.assert_allclose(out["tilt_mrad"][4], -out["tilt_mrad"][3], rtol=1e-3)
    np.testing.assert_allclose(FB[4], -FB[3], rtol=1e-3)
    assert FB[3] > 0 and FA[3] == pytest.approx(-FB[3], rel=1e-9)
    z = stack_positions(asm)
    span = (sum(z["inner_ring_B"]) - sum(z["inner_ring_A"])) / 2
    assert Pipeline.shared(asm).bearing_span_mm == pytest.approx(span)
    assert span == pytest.approx(asm.bearing.width_mm + asm.inner_spacer.length_mm)


@pytest.mark.parametrize("content,fragment", [
    ("T_ambient_C,radial_load_N\n20,0\n20,nan\n", "line 3, column 'radial_load_N': value is nan"),
    ("T_ambient_C,moment_Nmm\n20,abc\n", "line 2, column 'moment_Nmm': 'abc' is not a number"),
    ("T_ambient_C,moment_Nmm\n20,1e12\n", "column 'moment_Nmm': 1e+12 outside"),
    ("T_ambient_C,radial_load_N\n20,inf\n", "column 'radial_load_N': value is inf"),
])
def test_bad_load_values_are_one_line_and_exit_2(tmp_path, capsys, content, fragment):
    c = tmp_path / "c.csv"
    c.write_text(content)
    out = tmp_path / "o.csv"
    code = main(["simulate", str(CFG), str(c), "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and fragment in err[0], err
    assert not out.exists() and not list(tmp_path.glob(".o.csv*"))
