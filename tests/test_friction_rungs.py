"""The friction rungs of the model-form ladder (studies/diagnosis/friction_rungs.py):
which files get which rung, and the skip rule: a rung that acts through the speed is not tried on
data at one speed, one that acts through the temperature not on data at one temperature. The
references: the rungs' own definitions (docs/cli.md names) and the switch's blend, checked
against the pipeline of the changed assembly."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from studies.diagnosis import friction_rungs as fr
from studies.diagnosis.ladder import FormShare, ladder
from studies.model.config import load_shipped


def _rungs(name):
    return {r.name: r for r in ladder(load_shipped(name))}


def test_oil_file_gets_the_oil_rungs_and_the_solid_film_file_the_shear_rung():
    """seed 001 (oil, flooded, no oil quantity): torque_model_skf and rolling_ehl are switch
    candidates, starved_film is not tried (no oil quantity: the stated reason), no
    solid_film_pressure; seed 000 (MoS2 film): solid_film_pressure only."""
    oil, solid = _rungs("seed001"), _rungs("seed000")
    for n in ("torque_model_skf", "rolling_ehl"):
        assert isinstance(oil[n].candidate, FormShare) and oil[n].cost == "pair"
    assert oil["starved_film"].candidate is None and "oil_quantity_mg" in oil["starved_film"].why_not
    assert "solid_film_pressure" not in oil
    assert isinstance(solid["solid_film_pressure"].candidate, FormShare)
    assert not {"torque_model_skf", "rolling_ehl", "starved_film"} & solid.keys()


def test_a_form_the_file_uses_is_not_a_rung_and_a_stated_oil_quantity_is_tried():
    asm = load_shipped("seed001")
    skf = replace(asm, lubrication=replace(asm.lubrication, viscous_model="skf2004"))
    assert "torque_model_skf" not in {r.name for r in ladder(skf)}
    oiled = replace(asm, lubrication=replace(asm.lubrication, oil_quantity_mg=20.0))
    r = {r.name: r for r in ladder(oiled)}["starved_film"]
    assert isinstance(r.candidate, FormShare)
    assert r.configure(oiled).lubrication.viscous_model == "starved"
    assert r.configure(oiled).lubrication.oil_quantity_mg == 20.0


@pytest.mark.parametrize("name,file", [("rolling_ehl", "seed001"), ("torque_model_skf", "seed001"),
                                       ("solid_film_pressure", "seed000")])
def test_skipped_without_the_variation_the_rung_acts_through(name, file):
    """At one speed and one temperature every friction rung is skipped with its reason; a speed
    sweep makes the speed-law rungs (rolling_ehl, torque_model_skf) applicable but not the
    load-law rung; a temperature sweep the temperature rungs (torque_model_skf,
    solid_film_pressure) but not the speed-law rolling_ehl."""
    c = _rungs(file)[name].candidate
    flat = {"T_ambient_C": np.full(4, 20.0), "speed_rpm": np.full(4, 3000.0)}
    speed = {"T_ambient_C": np.full(4, 20.0), "speed_rpm": np.array([1e3, 2e3, 3e3, 4e3])}
    temp = {"T_ambient_C": np.array([-20.0, 0.0, 20.0, 60.0])}
    why = c.applicable(flat)
    assert why is not None and "do not vary" in why
    assert (c.applicable(speed) is None) == ("speed" in fr.NEEDS[name])
    assert (c.applicable(temp) is None) == ("temperature" in fr.NEEDS[name])


def test_a_preload_sweep_applies_the_load_law_rung():
    c = _rungs("seed000")["solid_film_pressure"].candidate
    assert c.applicable({"T_ambient_C": np.full(3, 20.0),
                         "preload_assembled_N": np.array([50.0, 100.0, 200.0])}) is None


def test_solid_film_pressure_form_is_the_singer_law():
    """The form's constants: tau0 22.5 MPa and alpha 0.001 (Singer et al. 1990, the middle of
    their 20-25 MPa and the order of their alpha), set through `[lubrication]`."""
    asm = load_shipped("seed000")
    lub = _rungs("seed000")["solid_film_pressure"].configure(asm).lubrication
    assert (lub.shear_strength, lub.tau0_MPa, lub.alpha_shear) == ("pressure", 22.5, 0.001)
