"""`bearingfem study heatup` (studies/runs/heatup.py): seed 003's ball-screw support heating up
through simulate's transient route, against the seed's qualitative findings (seed 003 section 3,
fig. 9, conclusions 1 and 2: the balls run hottest, the inner ring warmer than the outer, the heat
falls and levels off towards a thermal equilibrium; the difference between the rings and the
balls below 4 K)."""
import pytest

from studies.runs import STUDIES, heatup


def test_heatup_is_a_registered_study_and_its_short_coarse_run_writes_its_report(tmp_path):
    """The loop on a coarse mesh for 20 minutes at both speeds: tables, plots, report; the balls
    are already the hottest part (they take half of every contact's heat, Burton & Staph) and
    the faster pair is warmer everywhere (more heat: torque x speed)."""
    assert STUDIES["heatup"] == "studies.runs.heatup"
    found = heatup.run(tmp_path, progress=lambda s: None, mesh_factor=2.0, duration_s=1200.0,
                       images=False)
    for n in heatup.SPEEDS_RPM:
        assert (tmp_path / f"heatup_{n:.0f}rpm.csv").is_file()
        assert found[n].ball_hottest
    assert all(found[1500.0].T_end_C[p] > found[1000.0].T_end_C[p] for p in heatup.PARTS)
    for name in ("report.md", "preload.png", "torque.png", "heat.png"):
        assert (tmp_path / name).is_file(), name


@pytest.mark.slow
def test_heatup_reproduces_the_seeds_findings_at_equilibrium(tmp_path):
    """Three hours at 1000 and 1500 rpm on the study's mesh, against seed 003's published
    statements (section 3 on fig. 9, conclusions 1 and 2; `heatup.SEED_RING_BALL_DT_K`): the
    balls are the hottest part and the inner ring runs warmer than the outer at both speeds; the
    difference between the rings and the balls is below the seed's 4 K (stated at 1500 rpm;
    asserted at both); the inner-outer difference has shrunk from its largest value during the
    heat-up; the heat falls as the oil warms and thins and levels off (the run has reached
    equilibrium: every part changes by less than 0.05 K/h over the last 10 minutes, the heat by
    less than 0.1 % over the last 30). At that equilibrium each ball node's heat balance closes
    (conservation: what its contacts give it leaves through its two raceway conductances) to
    1 % of its heat (the reduced model's Galerkin residual at the node, the capacity term and the
    coupling's 10 s lag)."""
    found = heatup.run(tmp_path, progress=lambda s: None)
    for n, f in found.items():
        assert f.ball_hottest, n
        assert f.inner_outer_dT_K > 0.0, n
        assert f.ring_ball_dT_K < heatup.SEED_RING_BALL_DT_K, (n, f.ring_ball_dT_K)
        assert f.inner_outer_dT_K < f.inner_outer_dT_max_K, n
        assert f.heat_ratio_end_to_5min < 1.0, (n, f.heat_ratio_end_to_5min)
        assert f.end_rate_K_per_h < 0.05, (n, f.end_rate_K_per_h)
        assert f.heat_change_last_30min < 1e-3, (n, f.heat_change_last_30min)
    for n, f in found.items():
        for b in f.balances:
            assert abs(b.heat_W - b.out_W) < 1e-2 * b.heat_W, (n, b.bearing, b.heat_W, b.out_W)
    assert list(tmp_path.glob("field_1500rpm_*_temperature_C.png"))
