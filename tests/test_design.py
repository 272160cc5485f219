"""The athermal stack search: it finds a stack whose preload varies less over the range than the
shipped seed 000 stack at the same assembled preload, says why, and reads its range flags."""
import json
from dataclasses import replace

import pytest

from studies.app.cli import main
from studies.model.config import CONFIG_DIR, load_assembly, load_shipped
from studies.model.provenance import provenance
from studies.usecases import design_search as ds
from studies.model.columns import to_columns

THIN = CONFIG_DIR / "rig_thin_section_hub.toml"


@pytest.fixture(scope="module")
def search(tmp_path_factory):
    out = tmp_path_factory.mktemp("design")
    asm = load_shipped("seed000")
    res = ds.run(asm, -60.0, 80.0, out, provenance("design", {}), progress=lambda s: None,
                 materials=["TC4", "9Cr18", "6061"], length_factors=(0.5, 1.0),
                 screen_mesh_factor=4.0, confirm_mesh_factor=4.0)
    return asm, res, out


def test_search_finds_a_stack_with_less_preload_variation(search):
    asm, res, out = search
    P0 = asm.preload.assembled_N
    given = res.given
    assert given.is_given and given.metrics.preload_assembled_N == P0
    same_preload = [d for d in res.screened if d.metrics.feasible
                    and d.metrics.preload_assembled_N == P0 and not d.is_given]
    best = min(same_preload, key=lambda d: d.metrics.preload_variation)
    given_screen = next(d for d in res.screened
                        if d.is_given and d.metrics.preload_assembled_N == P0)
    assert best.metrics.preload_variation < 0.8 * given_screen.metrics.preload_variation
    # the report explains it with the split of the preload change
    report = (out / "report.md").read_text()
    assert "## Why the best design works" in report and "axial shifts" in report
    assert len(res.why.given) == len(res.why.best) == 2
    doc = json.loads((out / "design.json").read_text())
    assert {"designs", "pareto", "given", "range_C"} <= set(doc)
    assert all("preload_range_N" in d for d in doc["designs"])


def test_pareto_set_is_not_dominated(search):
    _, res, _ = search
    front = [d.metrics for d in res.pareto]
    feas = [d.metrics for d in res.screened if d.metrics.feasible]
    for d in front:
        for e in feas:
            better = (e.preload_variation <= d.preload_variation
                      and e.torque_max_Nmm <= d.torque_max_Nmm
                      and e.contact_pressure_margin >= d.contact_pressure_margin)
            strictly = (e.preload_variation < d.preload_variation
                        or e.torque_max_Nmm < d.torque_max_Nmm
                        or e.contact_pressure_margin > d.contact_pressure_margin)
            assert not (better and strictly)


@pytest.mark.parametrize("args,fragment", [
    (["--range", "80:-60"], "LOW must be below HIGH"),
    (["--range", "-60"], "expected LOW:HIGH"),
    (["--range", "-60:80", "--band", "1.2:0.8"], "LOW must be below HIGH"),
])
def test_bad_range_is_one_line_exit_2(tmp_path, capsys, args, fragment):
    out = tmp_path / "d"
    code = main(["design", str(CONFIG_DIR / "seed000_71807C_TC4.toml"), *args, "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and fragment in err[0] and not out.exists()


def test_inverse_search_finds_a_planted_trend():
    """Plant a trend: the preload change of one candidate stack, computed by `simulate` on that
    stack's assembly; the inverse search must return that stack first, with a miss at round-off
    of the preload, and every other stack missing by more."""
    import numpy as np

    from studies.model.pipeline import Pipeline, simulate_table
    from studies.usecases.design_search import candidates
    from studies.validation.inverse_rig import match_trend

    asm = load_shipped("seed000")
    stacks = candidates(asm, length_factors=(1.0,), materials=("TC4", "6061"),
                        ring_deltas_mm=(0.0, 1.0))
    planted = stacks[3]
    a = planted.assembly(asm)
    P = to_columns(simulate_table(a, {"T_ambient_C": np.array([-60.0, 20.0, 80.0])},
                       pipeline=Pipeline(a, mesh_factor=4.0)))["preload_N"]
    target = (P[0] - P[1], P[2] - P[1])
    m = match_trend(asm, stacks, (-60.0, 80.0), target, mesh_factor=4.0)
    assert m[0].stack == planted and m[0].miss_N <= 1e-9 * np.max(np.abs(P))
    assert all(x.miss_N > 1e-3 for x in m[1:])


# ------------------------------------------------------------------ preload band in newtons
def test_band_in_newtons_and_fractions():
    """`_metrics` reads the band as fractions of the assembled preload or in N: a made-up stack
    whose preload runs 60..140 N at 100 N assembled is inside 0.5..1.5 x and inside 44.5..445 N,
    outside 0.8..1.2 x and outside 70..445 N (limits by hand)."""
    import numpy as np

    asm = load_shipped("seed000")
    P = np.array([[60.0, 100.0, 140.0]])
    r = ds.StackAnswers(P, np.full_like(P, 1000.0),
                        {"inner": np.full_like(P, 10.0), "outer": np.full_like(P, 10.0)},
                        np.full_like(P, 1.0), 0)
    P0 = np.array([100.0])
    inside = [ds._metrics(asm, r, P0, b)[0].in_band for b in
              (ds.Band(0.5, 1.5), ds.Band(44.5, 445.0, absolute=True),
               ds.Band(0.8, 1.2), ds.Band(70.0, 445.0, absolute=True))]
    assert inside == [True, True, False, False]
    assert ds.Band(44.5, 445.0, absolute=True).limits_N(100.0) == (44.5, 445.0)
    assert ds.Band(0.8, 1.2).limits_N(50.0) == (40.0, 60.0)


@pytest.mark.parametrize("args,fragment", [
    (["--band", "0.8:1.2", "--band-N", "44.5:445"], "--band and --band-N"),
    (["--band-N", "445:44.5"], "LOW must be below HIGH"),
    (["--band-N=-5:445"], "at least 0 N"),
    (["--vary", "colour=red"], "--vary colour: unknown"),
    (["--vary", "spring_rate_N_per_mm=soft"], "takes numbers"),
    (["--vary", "spring_rate_N_per_mm=-1", "--vary", "preload_kind=spring"], "must be >= 0"),
    (["--vary", "spring_rate_N_per_mm=50"], "add --vary preload_kind=spring"),
    (["--vary", "inner_shaft_class=q5"], "inner_shaft_class"),
    (["--vary", "inner_shaft_class=H6"], "hole class"),
    (["--vary", "contact_angle_free_deg=75"], "outside 0..60"),
])
def test_bad_band_or_setting_is_one_line_exit_2(tmp_path, capsys, args, fragment):
    out = tmp_path / "d"
    code = main(["design", str(CONFIG_DIR / "seed000_71807C_TC4.toml"), "--range", "-60:80",
                 *args, "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and fragment in err[0] and not out.exists(), err


# ------------------------------------------------------------------ settings beside the stack
def test_fit_classes_move_the_mean_fit_by_the_iso_286_mid_band():
    """ISO 286-2 (30..50 mm): k5 is +2..+13 um (mid +7.5), J6 is -6..+10 um (mid +2); the
    seed 000 seats are 35 mm (shaft) and 47 mm (housing) without classes, so the settings move
    the mean inner interference by +7.5 um and the outer by -2 um."""
    asm = load_shipped("seed000")
    given = ds.Setting.given(asm)
    assert given.assembly(asm) == asm
    s = ds.settings_of(asm, {"inner_shaft_class": ("k5",), "outer_housing_class": ("J6",)})
    assert s[0] == given and len(s) == 2
    fi, fo = s[1].assembly(asm).mean_fits_um()
    fi0, fo0 = asm.mean_fits_um()
    assert fi - fi0 == pytest.approx(7.5, abs=1e-12) and fo - fo0 == pytest.approx(-2.0, abs=1e-12)


def test_settings_share_the_stack_fe_and_spring_limits(monkeypatch):
    """Three settings of one stack (the given position preload, a very stiff and a very soft
    spring) are one FE set-up (the set-up route called once), and the springs reach their
    limits: rate 1e12 N/mm (compliance 5e-13 mm/N per bearing, ~1e-8 of the bearing's) gives
    the position preload to 1e-6 relative, rate 1e-3 N/mm the constant-force spring to
    1e-3 N/mm x 1 mm (a bound on the loop's thermal length change)."""
    import numpy as np

    import fem.parametric as fp

    asm = load_shipped("seed000")
    calls = []
    real = fp.Family.setup
    monkeypatch.setattr(fp.Family, "setup", lambda self, spec: calls.append(1) or real(self, spec))
    g = ds.Setting.given(asm)
    stiff = replace(g, preload_kind="spring", spring_rate_N_per_mm=1e12)
    soft = replace(g, preload_kind="spring", spring_rate_N_per_mm=1e-3)
    const = replace(g, preload_kind="spring", spring_rate_N_per_mm=0.0)
    stack = ds.candidates(asm, length_factors=(1.0,), materials=["TC4"])[0]
    T, P0 = np.array([-60.0, 20.0, 80.0]), np.array([100.0])
    r = ds.evaluate_settings(asm, stack, (g, stiff, soft), T, P0, 4.0, parametric=True)
    assert len(calls) == 1
    np.testing.assert_allclose(r[1].preload_N, r[0].preload_N, rtol=1e-6)
    c = ds.evaluate_stack(asm, stack, T, P0, 4.0, parametric=True, setting=const)
    assert np.abs(r[2].preload_N - c.preload_N).max() <= 1e-3 * 1.0
    assert np.ptp(r[0].preload_N) > 10.0      # the position preload does move (not a no-op)


# ------------------------------------------------------------------ the why table adds up
def test_why_split_adds_up_and_interaction_is_second_order():
    """The four parts add up to the change (round-off: 1e-9 of the change), and the interaction
    of the radial and axial shifts is a second-order term: from 10 C to 1 C off the reference
    temperature its share of the change falls about tenfold (a bilinear term over a linear
    one; between 5x and 20x)."""
    asm = load_shipped("seed000")
    T0 = asm.T_ref_C
    small, large = ds.preload_split(asm, (T0 - 1.0, T0 - 10.0), 100.0, mesh_factor=4.0)
    for e in (small, large):
        assert abs(e.residual_N) <= 1e-9 * abs(e.change_N)
    share = [abs(e.interaction_N / e.change_N) for e in (small, large)]
    assert share[1] > 0 and 5.0 < share[1] / share[0] < 20.0


# ------------------------------------------------------------------ memory per stack
def test_no_fe_objects_outlive_a_stack(monkeypatch):
    """With automatic garbage collection off (a Dask worker's thread may not collect for many
    stacks), no FE stage (whose full FE, on the non-parametric route, holds the mesh and the
    factorisations: ~20 MB a stack) is left alive after a stack's task, and the family cache
    stays within its bound over more families than it keeps. Before: one FEStage per stack was
    left as cyclic garbage (object counts, not time)."""
    import gc

    import numpy as np

    import fem.parametric as fp
    from studies.model.stages.fe import FEStage

    asm = load_shipped("seed000")
    monkeypatch.setattr(fp, "FAMILIES_MAX", 2)
    stacks = ds.candidates(asm, length_factors=(0.5, 1.0, 1.5), materials=["TC4"])
    T, P0 = np.array([-60.0, 80.0]), np.array([100.0])
    def stages():       # FE stages alive, collected or not (other tests' caches keep some)
        return {id(o) for o in gc.get_objects() if isinstance(o, FEStage)}

    gc.collect()
    before = stages()
    gc.disable()
    try:
        for s in stacks:
            ds.evaluate_stack(asm, s, T, P0, 4.0, parametric=True)
        ds.evaluate_stack(asm, stacks[1], T, P0, 4.0, parametric=False)
        left = stages() - before
    finally:
        gc.enable()
    assert len({ds._family_of(s) for s in stacks}) == 3
    assert not left and len(fp._FAMILIES) <= 2


# ------------------------------------------------------------------ progress on a terminal
def test_progress_bar_on_a_terminal_only(monkeypatch):
    """The design command's stack bar (`progress_bar`, tqdm on stderr): drawn when stderr is a
    terminal (its 'done/total' counter), nothing when it is not (a file, a pipe, the test runner)."""
    import io
    import sys

    from studies.app.output import progress_bar

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    monkeypatch.delenv("BEARINGFEM_VERBOSE", raising=False)
    for stream, drawn in ((Terminal(), True), (io.StringIO(), False)):
        monkeypatch.setattr(sys, "stderr", stream)
        bar = progress_bar("stacks", "stack")
        for d in range(1, 8):
            bar(d, 7)
        assert ("stacks:" in stream.getvalue() and "/7" in stream.getvalue()) is drawn


def test_search_with_settings_keeps_the_given_numbers(tmp_path):
    """`--vary` adds settings beside the stacks without touching the rest: the assembly as given
    gets bit for bit the numbers of the search without settings, every setting of every stack is
    a design at every preload, and design.json carries each design's setting."""
    asm = load_shipped("seed000")
    kw = dict(progress=lambda s: None, materials=["TC4"], length_factors=(1.0,),
              screen_mesh_factor=4.0, confirm_mesh_factor=4.0)
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    plain = ds.run(asm, -60.0, 80.0, tmp_path / "a", provenance("design", {}), **kw)
    varied = ds.run(asm, -60.0, 80.0, tmp_path / "b", provenance("design", {}),
                    vary={"preload_kind": ("position", "spring"),
                          "spring_rate_N_per_mm": (0.0, 200.0)}, **kw)
    assert varied.n_settings == 3 and plain.n_settings == 1
    assert varied.n_designs == 3 * plain.n_designs
    assert varied.given.metrics == plain.given.metrics
    doc = json.loads((tmp_path / "b" / "design.json").read_text())
    kinds = {(d["preload_kind"], d["spring_rate_N_per_mm"]) for d in doc["screened"]}
    assert kinds == {("position", 0.0), ("spring", 0.0), ("spring", 200.0)}
    # a constant-force spring holds the preload at every temperature: its range is round-off
    const = [d for d in varied.screened if d.setting.preload_kind == "spring"
             and d.setting.spring_rate_N_per_mm == 0.0]
    assert all(d.metrics.preload_range_N <= 1e-9 * d.metrics.preload_assembled_N for d in const)


# ------------------------------------------------------------------ every fit counts
def test_a_sleeve_fit_that_opens_makes_the_design_infeasible():
    """Design said "fits closed: yes" while `simulate` flagged the sleeve fit
    open (the metrics read the inner and outer fits only). A made-up stack on the thin-section
    rig (its sleeve fit designed with interference, `tolerances.designed_closed`) whose inner and
    outer fits stay at 10 MPa and whose sleeve fit pressure falls to 0 at the hot end: not
    closed, not feasible, the sleeve named."""
    import numpy as np

    from studies.model.tolerances import designed_closed

    asm = load_assembly(THIN)
    assert designed_closed(asm)["sleeve"]
    P = np.array([[100.0, 100.0, 100.0]])
    ten = np.full_like(P, 10.0)
    r = ds.StackAnswers(P, np.full_like(P, 1000.0), {"inner": ten, "outer": ten,
                                                     "sleeve": np.array([[3.0, 1.0, 0.0]])},
                        np.full_like(P, 1.0), 0)
    m = ds._metrics(asm, r, np.array([100.0]), ds.Band(0.5, 1.5))[0]
    assert not m.fits_closed and not m.feasible and m.open_fits == ("sleeve",)


def test_an_infeasible_search_says_which_constraint_failed_everywhere(tmp_path):
    """The thin-section rig over its own range -45..70 C: `simulate` flags the sleeve fit open
    at the cold end (its check, a second route). Every design of the search must count it: no
    feasible design, an empty Pareto set, and `why` not null but naming fit_open_sleeve among
    the constraints every design failed; design.json and the report say it."""
    import numpy as np

    from studies.model.pipeline import Pipeline
    from studies.model.inputs import baseline_inputs

    asm = load_assembly(THIN)
    pl = Pipeline(asm, mesh_factor=4.0)
    res = pl.run(baseline_inputs({"T_ambient_C": np.array([-45.0])}, 1, asm.T_ref_C,
                                 asm.preload.assembled_N, asm.lubrication.speed_rpm))
    assert any(v.check.name == "fit_open_sleeve" for v in res.checks.violations())
    out = ds.run(asm, -45.0, 70.0, tmp_path, provenance("design", {}), progress=lambda s: None,
                 materials=["6061"], length_factors=(1.0,), screen_mesh_factor=4.0,
                 confirm_mesh_factor=4.0)
    assert not out.pareto and not any(d.metrics.feasible for d in out.screened)
    assert out.why is not None and "fit_open_sleeve" in out.why.failed_everywhere
    assert all("sleeve" in d.metrics.open_fits for d in out.screened)
    doc = json.loads((tmp_path / "design.json").read_text())
    assert "fit_open_sleeve" in doc["why"]["failed_everywhere"]
    assert "No feasible design" in (tmp_path / "report.md").read_text()


def test_the_liner_is_a_design_variable_through_the_one_route():
    """`--vary sleeve_material=..., sleeve_radial_thickness_mm=...,
    sleeve_shaft_class=...`. A liner of 17-4PH, 4.5 mm instead of the 6061 hub's 6 mm: the bore
    it sits in moves by twice the change (the [sleeve] relation, bearing OD + 2 t), and the
    search's numbers for that setting (the stack's family route, `fem.parametric`) are those of
    the pipeline on the same assembly written out by hand (its own FE set-up), to 1e-9 of the
    preload and of the sleeve fit pressure. Without a [sleeve] the keys are refused."""
    import numpy as np

    from studies.model.inputs import baseline_inputs
    from studies.model.pipeline import Pipeline
    from studies.model.checks import fit_pressure_MPa

    asm = load_assembly(THIN)
    settings = ds.settings_of(asm, {"sleeve_material": ("17-4PH",),
                                    "sleeve_radial_thickness_mm": (4.5,)})
    s = next(x for x in settings if x.sleeve_material == "17-4PH"
             and x.sleeve_radial_thickness_mm == 4.5)
    a = s.assembly(asm)
    assert a.housing.bore_diameter_mm == pytest.approx(asm.bearing.outside_diameter_mm + 2 * 4.5,
                                                       abs=1e-9)
    assert "sleeve 17-4PH" in s.label(ds.Setting.given(asm))
    T = np.array([-45.0, 20.0, 70.0])
    P0 = np.array([asm.preload.assembled_N])
    stack = ds.candidates(asm, materials=["17-4PH"], length_factors=(1.0,))[0]
    got = ds.evaluate_settings(asm, stack, (s,), T, P0, 4.0, parametric=True)[0]
    by_hand = replace(asm, sleeve=replace(asm.sleeve, material="17-4PH", radial_thickness_mm=4.5),
                      housing=replace(asm.housing, bore_diameter_mm=asm.bearing.outside_diameter_mm + 9.0))
    res = Pipeline(by_hand, mesh_factor=4.0).run(baseline_inputs(
        {"T_ambient_C": T}, T.size, asm.T_ref_C, float(P0[0]), asm.lubrication.speed_rpm))
    assert np.allclose(got.preload_N[0], res.preload_N, rtol=1e-9, atol=1e-9 * np.abs(res.preload_N).max())
    p = fit_pressure_MPa(res, "sleeve")
    assert np.allclose(got.fit_pressure_MPa["sleeve"][0], p, rtol=1e-9, atol=1e-9 * np.abs(p).max())
    plain = ds.evaluate_settings(asm, stack, (ds.Setting.given(asm),), T, P0, 4.0, parametric=True)[0]
    assert np.abs(plain.fit_pressure_MPa["sleeve"][0] - p).max() > 0.1 * np.abs(p).max()  # it acts
    with pytest.raises(ds.DesignError, match="no \\[sleeve\\]"):
        ds.settings_of(load_shipped("seed000"), {"sleeve_material": ("6061",)})
