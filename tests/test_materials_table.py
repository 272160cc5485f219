"""A config's own materials (`[materials.NAME]` tables): used by name like the library's, reaching
every part of the chain (free-part interference, FE set-up, bearing geometry); bad tables are one
line naming the file and key, exit 2."""
import numpy as np
import pytest

import bearingfem
from analytic.bearing.geometry import BearingGeometry
from analytic.materials import get_material, material_from_table
from studies.model.config import CONFIG_DIR, ConfigError, load_assembly
from refusal import simulate_is_refused

SEED000 = CONFIG_DIR / "seed000_71807C_TC4.toml"
D_OUTER_FIT_MM = 47.0          # seed000: housing bore = 71807C outside diameter
DCTE_PER_K = 1.0e-6


def _with_housing(tmp_path, table: str, name="MyTi"):
    text = SEED000.read_text()
    head, sep, rest = text.partition("[housing]\n")
    rest = rest.replace('material = "TC4"', f'material = "{name}"', 1)
    p = tmp_path / "asm.toml"
    p.write_text(head + sep + rest + "\n" + table)
    return p


def test_user_material_reaches_the_free_fit(tmp_path):
    """Housing CTE raised by 1e-6/K: the outer fit's free diametral interference changes by
    -D dalpha dT (closed form, D = 47 mm) between 20 and 80 C, everything else equal."""
    cte = get_material("TC4").alpha_per_K + DCTE_PER_K
    cfg = _with_housing(tmp_path, f'[materials.MyTi]\nbase = "TC4"\ncte_per_K = {cte!r}\n')
    asm = load_assembly(cfg)
    assert asm.material("housing").alpha_per_K == cte
    assert asm.material("housing").E_MPa == get_material("TC4").E_MPa
    rows = {"T_ambient_C": [20.0, 80.0]}
    user = bearingfem.simulate(asm, rows)
    lib = bearingfem.simulate(SEED000, rows)
    change_um = np.diff(user["interference_outer_um"])[0] - np.diff(lib["interference_outer_um"])[0]
    expected_um = -D_OUTER_FIT_MM * DCTE_PER_K * 60.0 * 1e3
    # relative to the 2.82 um closed-form change (round-off of 5 um terms)
    assert change_um == pytest.approx(expected_um, rel=1e-9)
    # the FE saw the stiffer-growing housing too: the outer fit pressure at 80 C is lower
    assert user["fit_pressure_outer_MPa"][1] < lib["fit_pressure_outer_MPa"][1]


def test_user_ball_material_in_the_bearing_geometry():
    """A user's ball material equal to the library's Si3N4 under another name gives the same
    geometry; overriding a library name replaces only the keys given."""
    si = get_material("Si3N4")
    mine = material_from_table("MyCeramic", {"base": "Si3N4"})
    spec = load_assembly(SEED000).bearing
    from dataclasses import replace
    g_user = BearingGeometry.from_spec(replace(spec, ball_material="MyCeramic"), (mine,))
    g_lib = BearingGeometry.from_spec(replace(spec, ball_material="Si3N4"))
    assert g_user.ball.E_MPa == si.E_MPa and g_user.ball.nu == si.nu
    assert g_user.ball.name == "MyCeramic" and g_lib.ball.name == "Si3N4"
    over = material_from_table("9Cr18", {"E_MPa": 190e3})
    assert over.E_MPa == 190e3 and over.alpha_per_K == get_material("9Cr18").alpha_per_K
    new = material_from_table("Invar36", {"E_MPa": 141e3, "nu": 0.26, "cte_per_K": 1.3e-6,
                                          "density_kg_m3": 8050, "conductivity_W_mK": 10.4,
                                          "specific_heat_J_kgK": 515})
    assert new.dalpha_per_K2 == 0.0 and new.density_N_s2_mm4 == pytest.approx(8.05e-9, rel=1e-12)


@pytest.mark.parametrize("table,message", [
    ('[materials.MyTi]\nE_MPa = 1.0e5\n', "materials.MyTi: missing nu"),
    ('[materials.MyTi]\nbase = "Unobtainium"\n', "materials.MyTi.base: unknown material 'Unobtainium'"),
    ('[materials.MyTi]\nbase = "TC4"\nnu = 0.7\n', "materials.MyTi.nu: must be in 0..0.5"),
    ('[materials.MyTi]\nbase = "TC4"\nyoung = 1\n', "materials.MyTi.young: unknown key"),
    ('[materials.MyTi]\nbase = "TC4"\nE_MPa = "hard"\n', "materials.MyTi.E_MPa: must be a finite number"),
    ('[materials]\nMyTi = 3\n', "[materials]: give one table per material"),
    ('', "housing.material: unknown material 'MyTi'"),
])
def test_bad_material_tables_one_line_exit_2(tmp_path, capsys, table, message):
    cfg = _with_housing(tmp_path, table)
    with pytest.raises(ConfigError, match=r"asm\.toml: " + message.replace("[", r"\[").replace("]", r"\]")
                       .replace("(", r"\(").replace(".", r"\.")):
        load_assembly(cfg)
    simulate_is_refused(tmp_path, capsys, cfg, message)
