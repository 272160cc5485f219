"""Rectangle and grooved ring sections (`[mesh] ring_section`) against a closed form in the one
state where the groove cannot matter: a stack with clearance fits that stay open and compliant
clamps at a uniform temperature and no speed is stress-free, so every part grows freely,
u = theta_part (x - x_ref). The groove-centre shifts then follow from the geometry alone:

- radial, per bearing: dr = theta_ring (r_c,inner - r_c,outer) (a free ring's centre circle grows
  with the ring; shaft and housing do not reach it through an open fit);
- axial, between the bearings: the inner groove centres move apart by the free growth of the
  chain ring A / inner spacer / ring B between them, the outer ones by that of ring A / outer
  spacer / ring B, so dz_A - dz_B = -(that of the inner chain) + (that of the outer chain).

Both sections must give these (P2 elements hold a linear field exactly): the grooved one
through the circle fitted to its displaced groove, the rectangle through a raceway point plus
the ring's strain times the centre offset. The differences studied in docs/ring_sections.md
therefore come from stiffness (fits, clamps, spin), not from how the shift is read off."""
import tomllib

import numpy as np
import pytest

from studies.model.config import CONFIG_DIR, assembly_from_dict
from studies.model.pipeline import Pipeline, table_inputs
from studies.model.stack import grooves_of, section_from_assembly

T_C = np.array([-60.0, 80.0])


def _free_stack(section: str):
    raw = tomllib.loads((CONFIG_DIR / "seed000_71807C_TC4.toml").read_text())
    raw["fits"]["inner_interference_um"] = -20.0     # TC4 vs 9Cr18 closes at most ~5 um here
    raw["fits"]["outer_interference_um"] = -20.0
    raw["nut"]["clamp"] = "compliant"
    raw["cover"]["clamp"] = "compliant"
    raw.setdefault("mesh", {}).update(ring_section=section, target_error=1e-2)
    return assembly_from_dict(raw, "free_stack.toml")


def _chain_growth_mm(a, rings, spacer, z_from, z_to, T):
    """Free growth of the axial distance between z_from (in ring A) and z_to (in ring B)."""
    rects = {r.part: r for r in section_from_assembly(a).rects}
    ra, sp, rb = rects[rings[0]], rects[spacer], rects[rings[1]]
    assert z_from < ra.z1_mm and rb.z0_mm < z_to                  # the chain: A, spacer, B
    assert (ra.z1_mm, sp.z1_mm) == pytest.approx((sp.z0_mm, rb.z0_mm))
    th_r = a.material("inner_ring").thermal_strain(T, a.T_ref_C)
    th_s = a.material(spacer).thermal_strain(T, a.T_ref_C)
    return th_r * (ra.z1_mm - z_from) + th_s * (sp.z1_mm - sp.z0_mm) + th_r * (z_to - rb.z0_mm)


@pytest.mark.parametrize("section", ["rectangle", "grooved"])
def test_free_stack_groove_shifts_are_the_free_thermal_growth(section):
    a = _free_stack(section)
    fe = Pipeline(a).fe(table_inputs(a, {"T_ambient_C": T_C,
                                                       "speed_rpm": np.zeros(T_C.size)}))
    assert np.all(fe.fit_pressure_MPa == 0.0)                     # the fits stayed open
    (riA, ziA), (riB, ziB), (roA, zoA), (roB, zoB) = [(g.r_mm, g.z_mm) for g in grooves_of(a)]
    th_r = a.material("inner_ring").thermal_strain(T_C, a.T_ref_C)
    scale = np.abs(th_r) * riA                                     # a ring's free radial growth
    assert fe.dr_mm[0] == pytest.approx(th_r * (riA - roA), abs=1e-8 * scale.max())
    assert fe.dr_mm[1] == pytest.approx(th_r * (riB - roB), abs=1e-8 * scale.max())
    inner = _chain_growth_mm(a, ("inner_ring_A", "inner_ring_B"), "inner_spacer", ziA, ziB, T_C)
    outer = _chain_growth_mm(a, ("outer_ring_A", "outer_ring_B"), "outer_spacer", zoA, zoB, T_C)
    assert abs(inner - outer).min() > 1e-5                        # the spacers differ: dz moves
    assert fe.dz_mm[0] - fe.dz_mm[1] == pytest.approx(outer - inner, abs=1e-8 * scale.max())
