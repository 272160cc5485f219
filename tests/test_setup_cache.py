"""The FE set-up cached across runs (fem/setup.py): the cached route gives the numbers of the
route through the full FE, a second run skips the FE entirely, a damaged or foreign file is
rebuilt with one warning, and every input the numbers depend on changes the key."""
import dataclasses

import numpy as np
import pytest

import fem.setup as fs
from analytic.materials import get_material
from fem.setup import CompliancePlan, SetupSpec, cached_setup, compute_setup, full_fe, read_setup
from meshes.section import two_cylinder_section
from studies.model.config import load_shipped
from studies.model.inputs import baseline_inputs
from studies.model.pipeline import Pipeline
from studies.model.columns import to_columns

SEC = two_cylinder_section(0.0, 10.0, 15.0, "TC4", "9Cr18", 8.0, size_mm=2.0, fit_size_mm=1.0)
PTS = np.array([[15.0], [4.0]])                        # one probe point (r, z) in mm
PLAN = CompliancePlan((1.0, -1.0), (0.0025,))   # keys only: a bearing stack has four raceways


def spec(section=SEC, contact="frictionless", plan=None, materials=None):
    return SetupSpec.of(section, contact, PTS, plan, materials)


@pytest.fixture()
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("BEARINGFEM_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache" / "setups"


def no_fe(_spec):
    raise AssertionError("the full FE was built")


def outputs_equal(a: dict, b: dict) -> None:
    """Every output equal to round-off of its own magnitude (1e-12 of the largest value)."""
    assert a.keys() == b.keys()
    for k in a:
        x, y = np.asarray(a[k], float), np.asarray(b[k], float)
        scale = np.abs(y[np.isfinite(y)]).max(initial=0.0)
        np.testing.assert_array_equal(np.isfinite(x), np.isfinite(y), err_msg=k)
        ok = np.isfinite(y)
        assert np.abs(x[ok] - y[ok]).max(initial=0.0) <= 1e-12 * scale, k


def _inputs(asm, T):
    T = np.asarray(T, float)
    return baseline_inputs({"T_ambient_C": T, "axial_load_N": np.linspace(-20, 20, T.size)},
                           T.size, asm.T_ref_C, asm.preload.assembled_N, asm.lubrication.speed_rpm)


@pytest.mark.parametrize("contact", ["frictionless", "bonded"])
def test_cached_and_uncached_pipelines_give_the_same_outputs(cache, monkeypatch, contact):
    asm = load_shipped("seed000")
    asm = dataclasses.replace(asm, fits=dataclasses.replace(asm.fits, contact=contact))
    inp = _inputs(asm, np.linspace(-60.0, 80.0, 9))      # the outer fit closes near 41 C
    reference = to_columns(Pipeline(asm, mesh_factor=3.0, cache=False).run(inp))
    cold = Pipeline(asm, mesh_factor=3.0)                   # computes and stores the set-up
    assert list(cache.glob("setup_*.npz"))
    outputs_equal(to_columns(cold.run(inp)), reference)
    monkeypatch.setattr(fs, "full_fe", no_fe)               # a second run: no FE at all
    warm = Pipeline(asm, mesh_factor=3.0)
    out = to_columns(warm.run(inp))
    outputs_equal(out, reference)
    assert warm._full is None and warm.ndofs == cold.ndofs
    assert warm.compliance_mm_per_N == cold.compliance_mm_per_N > 0


def test_a_field_after_a_cached_set_up_builds_the_fe_on_demand(cache):
    asm = load_shipped("seed000")
    inp = _inputs(asm, [80.0])
    Pipeline(asm, mesh_factor=3.0)
    warm = Pipeline(asm, mesh_factor=3.0)
    f = warm.field(inp)
    load = warm.model.unit_loads @ f.theta + warm.omega2(inp)[0] * warm.model.spin_load
    sol = warm.solver.solve(load, warm.deltas_mm(*warm.fits_um(inp))[0])
    np.testing.assert_allclose(f.u_mm, sol.u, rtol=0, atol=1e-8 * np.abs(sol.u).max())


def test_stored_arrays_read_back_exactly(cache):
    s = spec()
    direct = compute_setup(s, full_fe(s))
    stored = cached_setup(s, lambda: full_fe(s))
    again = cached_setup(s, lambda: no_fe(s))
    for got in (stored, again):
        for f in dataclasses.fields(direct.condensed):
            np.testing.assert_array_equal(getattr(got.condensed, f.name),
                                          getattr(direct.condensed, f.name))
        assert np.isnan(got.compliance_mm_per_N) and np.isnan(direct.compliance_mm_per_N)
        assert (got.part_names, got.fit_names, got.ndofs) == (direct.part_names, direct.fit_names,
                                                              direct.ndofs)


def _rewrite(path, redigest=False, **changes):
    with np.load(path) as z:
        a = {k: z[k] for k in z.files}
    a.update(changes)
    if redigest:                          # a consistent file with inconsistent content
        a.pop("digest")
        a["digest"] = np.array(fs._digest(a))
    with open(path, "wb") as fh:
        np.savez(fh, **a)


@pytest.mark.parametrize("damage,reason", [
    ("truncated", "unreadable"), ("empty", "unreadable"), ("random bytes", "unreadable"),
    ("folder", "unreadable"), ("other inputs", "made for other inputs"),
    ("changed number", "does not match its digest"), ("wrong shape", "array B has shape"),
    ("not finite", "non-finite")])
def test_a_damaged_or_foreign_set_up_is_rebuilt_with_one_warning(cache, capsys, damage, reason):
    s = spec()
    good = cached_setup(s, lambda: full_fe(s))
    path = cache / f"setup_{s.key()}.npz"
    if damage == "truncated":
        path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    elif damage == "empty":
        path.write_bytes(b"")
    elif damage == "random bytes":
        path.write_bytes(np.random.default_rng(0).bytes(4096))
    elif damage == "folder":
        path.unlink()
        path.mkdir()
    elif damage == "other inputs":
        other = spec(SEC.scaled(0.8))
        cached_setup(other, lambda: full_fe(other))
        path.write_bytes((cache / f"setup_{other.key()}.npz").read_bytes())
    elif damage == "changed number":         # readable, but not what was written (digest)
        _rewrite(path, A=good.condensed.A * (1 + 1e-9))
    elif damage == "wrong shape":
        _rewrite(path, redigest=True, B=good.condensed.B[:-1])
    else:
        _rewrite(path, redigest=True, A=np.where(good.condensed.A > 0, np.inf, good.condensed.A))
    capsys.readouterr()
    rebuilt = cached_setup(s, lambda: full_fe(s))
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "warning" in err[0] and str(path) in err[0] and reason in err[0], err
    np.testing.assert_array_equal(rebuilt.condensed.A, good.condensed.A)
    cached_setup(s, lambda: no_fe(s))                       # sound again, no warning
    assert capsys.readouterr().err == ""


def test_a_file_that_does_not_read_back_never_enters_the_cache(cache, monkeypatch):
    real = fs.write_setup

    def short_write(setup, tmp):
        real(setup, tmp)
        tmp.write_bytes(tmp.read_bytes()[:300])
    monkeypatch.setattr(fs, "write_setup", short_write)
    s = spec()
    with pytest.raises(fs.SetupError, match="wrote an unusable FE set-up"):
        cached_setup(s, lambda: full_fe(s))
    assert not list(cache.glob("setup_*"))


def test_every_input_of_the_set_up_changes_its_key(monkeypatch):
    base = spec(plan=PLAN)
    tc4 = get_material("TC4")
    changed = {
        "material E": spec(plan=PLAN, materials={"shaft": dataclasses.replace(tc4, E_MPa=114e3)}),
        "material nu": spec(plan=PLAN, materials={"shaft": dataclasses.replace(tc4, nu=0.33)}),
        "mesh size": spec(SEC.scaled(0.9), plan=PLAN),
        "geometry": spec(two_cylinder_section(0.0, 10.0, 15.5, "TC4", "9Cr18", 8.0, size_mm=2.0,
                                              fit_size_mm=1.0), plan=PLAN),
        "contact": spec(contact="bonded", plan=PLAN),
        "compliance fit": spec(plan=CompliancePlan((1.0, -1.0), (0.003,))),
        "no compliance": spec(),
    }
    keys = {name: s.key() for name, s in changed.items()}
    assert base.key() not in keys.values() and len(set(keys.values())) == len(keys)
    k0 = base.key()
    assert spec(plan=PLAN).key() == k0                      # equal inputs, equal key
    monkeypatch.setattr(fs, "FORMAT", fs.FORMAT + 1)
    assert base.key() != k0
    monkeypatch.undo()
    monkeypatch.setattr(fs, "__version__", "99.0")
    assert base.key() != k0


def test_a_file_of_other_inputs_is_refused_when_read(cache):
    s = spec()
    cached_setup(s, lambda: full_fe(s))
    other = spec(materials={"shaft": dataclasses.replace(get_material("TC4"), E_MPa=100e3)})
    with pytest.raises(fs.SetupError, match="other inputs"):
        read_setup(cache / f"setup_{s.key()}.npz", other)


def test_the_lubricant_does_not_change_the_set_up():
    """What the FE does not depend on shares one stored set-up."""
    from studies.model.stack import section_from_assembly

    asm = load_shipped("seed000")
    other = dataclasses.replace(asm, lubrication=dataclasses.replace(asm.lubrication,
                                                                     friction_coefficient=0.2))
    keys = [SetupSpec.of(section_from_assembly(a), a.fits.contact, np.zeros((2, 1)), None).key()
            for a in (asm, other)]
    assert keys[0] == keys[1]


def test_an_unusable_cache_location_is_one_warning_for_meshes_and_set_ups(tmp_path, monkeypatch,
                                                                           capsys):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("BEARINGFEM_CACHE", str(blocker))
    s = spec()
    got = cached_setup(s, lambda: full_fe(s))                 # meshes, then stores the set-up
    again = cached_setup(s, lambda: no_fe(s))                 # from the temporary folder
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cache" in err[0] and str(blocker) in err[0], err
    np.testing.assert_array_equal(again.condensed.A, got.condensed.A)
    assert blocker.read_text() == "not a folder"


def test_the_compliance_started_from_the_condensed_state_is_the_closed_fits_iteration():
    """The set-up starts the assembled state's FE active set from the condensed problem's
    (`fem.compliance.assembled_closed_set`) instead of the closed fits: the same contact state,
    so the compliance is the same number, bit for bit, as the iteration from the closed fits (a
    second route through the full FE), with fewer factorisations. The case: the cartridge rig
    (a force clamp, two layers) on a mesh coarsened 4x, where the iteration from the closed fits
    factorises 7 contact states (measured) to reach the assembled one, and the start from the
    condensed state factorises that one only (then, for both, the state with the faces closed)."""
    from fem.compliance import assembled_closed_set, preload_path_compliance_mm_per_N
    from fem.solver import condense
    from studies.model.config import CONFIG_DIR, load_assembly

    s = Pipeline(load_assembly(CONFIG_DIR / "rig_cartridge_sleeve.toml"), mesh_factor=4.0).spec
    signs, delta = np.array(s.compliance.signs), np.array(s.compliance.delta_assembled_mm)
    cold = full_fe(s)
    c_cold = preload_path_compliance_mm_per_N(cold.solver, cold.probe, signs, delta)
    warm = full_fe(s)
    condensed = condense(warm.solver, warm.probe)           # 1 factorisation: all pairs open
    first = assembled_closed_set(condensed, warm.solver, delta)
    c_warm = preload_path_compliance_mm_per_N(warm.solver, warm.probe, signs, delta, first)
    assert c_warm == c_cold and np.isfinite(c_cold) and c_cold > 0
    assert warm.solver.n_factorisations - 1 == 2 < cold.solver.n_factorisations
    assert compute_setup(s, full_fe(s)).compliance_mm_per_N == c_cold
