"""Sobol' indices (studies/model/sobol.py, SALib) against the closed form of a linear model:
Y = sum a_i X_i with independent X_i has S_i = ST_i = a_i^2 Var(X_i) / sum_j a_j^2 Var(X_j)
(Sobol' 2001; Var = width^2 / 12 uniform, sd^2 normal)."""
import numpy as np
import pytest

from studies.model import sobol


@pytest.mark.parametrize("kind", ["uniform", "normal"])
def test_first_order_and_total_indices_of_a_linear_model_are_the_variance_shares(kind):
    a = {"x1": 2.0, "x2": -1.0, "x3": 0.5, "x4": 0.0}
    if kind == "uniform":
        inputs = {"x1": ("uniform", -4.0, 6.0), "x2": ("uniform", -6.0, 0.0),
                  "x3": ("uniform", 0.0, 12.0), "x4": ("uniform", -1.0, 1.0)}
        var = {k: (hi - lo) ** 2 / 12 for k, (_, lo, hi) in inputs.items()}
    else:
        inputs = {"x1": ("normal", 1.0, 10 / 6), "x2": ("normal", -3.0, 1.0),
                  "x3": ("normal", 6.0, 2.0), "x4": ("normal", 0.0, 1 / 3)}
        var = {k: sd ** 2 for k, (_, _, sd) in inputs.items()}
    total = sum(a[k] ** 2 * var[k] for k in a)
    exact = np.array([a[k] ** 2 * var[k] / total for k in a])
    res = sobol.indices(inputs, lambda X: sum(a[k] * X[k] for k in a), n_base=4096, seed=3)[0]
    assert res.names == tuple(a)
    # within 3 bootstrap 95 % half-widths (about 6 standard errors) of the closed form; the
    # input with no effect: its share 0 within the same band
    assert np.all(np.abs(res.S1 - exact) <= 3 * res.S1_conf + 1e-12), (res.S1, exact, res.S1_conf)
    assert np.all(np.abs(res.ST - exact) <= 3 * res.ST_conf + 1e-12), (res.ST, exact, res.ST_conf)
    assert res.S1_conf.max() < 0.05          # the test can tell shares 0.05 apart


def test_preload_indices_follow_the_surface_variances_at_the_reference_temperature(tmp_path):
    """Only the inner fit toleranced (shaft [-4, 6], bore [-6, 0] um, uniform) and the fits far
    from opening (+20 um nominal): the preload then depends on shaft - bore alone, nearly
    linearly, so the indices are the variance shares 100/136 and 36/136 (closed form above),
    within 3 half-widths plus 0.02 for the curvature of the preload in the interference."""
    from studies.model.config import CONFIG_DIR, load_assembly

    text = (CONFIG_DIR / "seed000_71807C_TC4.toml").read_text()
    text = text.replace("inner_interference_um = 5.0", "inner_interference_um = 20.0", 1)
    text = text.replace("[fits]\n", "[fits]\ninner_shaft_deviation_um = [-4.0, 6.0]\n"
                        "inner_ring_bore_deviation_um = [-6.0, 0.0]\n", 1)
    assert "inner_interference_um = 20.0" in text
    (tmp_path / "a.toml").write_text(text + "\n[mesh]\nsize_mm = 2.0\nfit_size_mm = 0.5\n")
    asm = load_assembly(tmp_path / "a.toml")
    res = sobol.preload_indices(asm, {"T_ambient_C": np.array([asm.T_ref_C])}, n_base=512)[0]
    exact = {"inner_shaft": 100 / 136, "inner_ring_bore": 36 / 136}
    for i, n in enumerate(res.names):
        assert abs(res.S1[i] - exact[n]) <= 3 * res.S1_conf[i] + 0.02, (n, res.S1[i], res.S1_conf[i])
