"""`bearingfem study tvac` (studies/validation/tvac.py): seed 000's stack in a thermal-vacuum cycle
through simulate's transient route, against independent statements: the maximum principle of
heat conduction (with next to no heat of its own the stack stays between the shroud's extremes)
and the given-temperature route (the preload of the computed part temperatures, given as
uniform part temperatures, differs from the transient's only by the spread inside the parts)."""
import pandas as pd

import bearingfem
from studies.validation import STUDIES, tvac


def test_tvac_cycle_on_a_coarse_mesh(tmp_path):
    """The cycle compressed 10 x (1.5 h), 20 s steps, coarse mesh: files written; every part
    temperature and the field extremes within the shroud's range widened by the friction heat's
    rise (heat / radiating conductance, < 0.5 K here: a few mW against ~0.02 W/K); the last
    row's preload equals the given route's at the computed part temperatures within
    |dP/dT| x (T_max - T_min) (the non-uniformity the part means do not carry)."""
    assert STUDIES["tvac"] == "studies.validation.tvac"
    s = tvac.run(tmp_path, progress=lambda m: None, mesh_factor=2.0, time_scale=0.1,
                 images=False, dt_s=20.0)
    for name in ("tvac.csv", "tvac.png", "report.md"):
        assert (tmp_path / name).is_file(), name
    rows = pd.read_csv(tmp_path / "tvac.csv")
    lo, hi = rows["T_sink_C"].min(), rows["T_sink_C"].max()
    assert rows["heat_bearing_W"].max() < 0.02
    rise = 0.5
    assert rows["T_min_C"].min() >= lo - 1e-9 and rows["T_max_C"].max() <= hi + rise
    assert s.T_range_C["housing"][1] < hi and s.T_range_C["housing"][0] > lo   # it lags
    # the given route at the last row's part temperatures
    asm = bearingfem.load_assembly("studies/configs/seed000_71807C_TC4.toml")
    last = rows.iloc[-1]
    parts = ("shaft", "inner_ring", "ball", "outer_ring", "housing", "spacer")
    # rows: the part temperatures, all 1 K warmer, all 1 K colder (the slope dP/dT)
    given = {f"T_{p}_C": [last[f"T_{p}_C"], last[f"T_{p}_C"] + 1.0, last[f"T_{p}_C"] - 1.0]
             for p in parts}
    g = bearingfem.simulate(asm, given)["preload_N"].to_numpy()
    dPdT = abs(g[1] - g[2]) / 2.0
    spread = last["T_max_C"] - last["T_min_C"]
    assert abs(last["preload_N"] - g[0]) <= dPdT * spread
