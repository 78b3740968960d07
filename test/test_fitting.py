"""The one fitting stack: every core type fits in calibration and diagnosis alike; bad names are clear errors."""
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO
from polyforce_ros.physics import fitting
from polyforce_ros.physics.identification import fit_creep
from polyforce_ros.physics.viscoelastic import MODEL_TYPES, Burgers2, Burgers3, Zener2, Zener3, simulate_deformation
from polyforce_ros.sim import profiles


def test_information_criteria_state_their_sample_count():
    aic, bic = fitting.information_criteria(rss=4.0, n=100, p=3)
    assert aic == pytest.approx(100 * np.log(0.04) + 6) and bic == pytest.approx(100 * np.log(0.04) + 3 * np.log(100))
    with pytest.raises(ValueError):
        fitting.information_criteria(1.0, 0, 1)


def test_block_jackknife_standard_errors_match_least_squares_on_white_noise():
    """Over many records, the jackknife variance of a line's slope and intercept averages to the textbook one
    when the blocks are drawn at random; contiguous blocks (as in time) make it conservative, never optimistic."""
    rng = np.random.default_rng(7)
    n, k, sigma = 1000, 5, 0.1
    x = np.linspace(0.0, 1.0, n)
    a = np.column_stack([x, np.ones(n)])
    analytic = sigma * np.sqrt(np.diag(np.linalg.inv(a.T @ a)))
    random_blocks = np.array_split(rng.permutation(n), k)
    contiguous_blocks = np.array_split(np.arange(n), k)
    var = {"random": np.zeros(2), "contiguous": np.zeros(2)}
    for _ in range(400):
        y = 2.0 * x + 0.5 + rng.normal(0.0, sigma, n)
        for name, blocks in (("random", random_blocks), ("contiguous", contiguous_blocks)):
            left_out = [np.linalg.lstsq(np.delete(a, b, 0), np.delete(y, b), rcond=None)[0] for b in blocks]
            var[name] += fitting.block_jackknife_standard_errors(left_out) ** 2 / 400
    assert np.sqrt(var["random"]) == pytest.approx(analytic, rel=0.15)
    assert np.all(np.sqrt(var["contiguous"]) >= analytic * 0.9)
    assert fitting.block_jackknife_standard_errors([[1.0, 2.0]] * 3).tolist() == [0.0, 0.0]
    with pytest.raises(ValueError):
        fitting.block_jackknife_standard_errors([[1.0, 2.0]])


@pytest.mark.parametrize("kind", sorted(MODEL_TYPES))
def test_every_model_type_has_finite_starts_inside_the_bounds(kind):
    starts = fitting.starts_from_compliance(kind, 0.2, 0.35, 1e-4, (1.0, 10.0), hold_s=30.0)
    for theta in starts:
        assert theta.size == len(MODEL_TYPES[kind].parameter_names())
        assert np.all(np.isfinite(theta)) and np.all(theta > fitting.LOG_BOUNDS[0]) and np.all(theta < fitting.LOG_BOUNDS[1])
        MODEL_TYPES[kind].from_vector(np.exp(theta)).relaxation()  # a usable model


@pytest.mark.parametrize("truth", [Zener2(5.0, 12.0, 40.0, 20.0, 600.0), Burgers2(5.0, 12.0, 5000.0, 40.0, 20.0, 600.0),
                                   Zener3(5.0, 12.0, 6.0, 20.0, 200.0, 15.0, 1500.0),
                                   Burgers3(5.0, 12.0, 5000.0, 6.0, 20.0, 200.0, 15.0, 1500.0)])
def test_creep_calibration_fits_the_two_and_three_kelvin_types(truth):
    t, f = profiles.creep(rate_hz=20.0)
    v = simulate_deformation(truth, t, f) + 0.03
    fit = fit_creep(truth.kind, t, f, v)  # raised KeyError for zener2 before the one fitting stack
    assert fit.kind == truth.kind and fit.r2 > 0.9999 and abs(fit.offset_v - 0.03) < 1e-3


def test_unknown_model_types_are_clear_errors():
    with pytest.raises(ValueError, match="nonsense"):
        fitting.check_model_types(["zener", "nonsense"])
    with pytest.raises(ValueError, match="unknown model type"):
        fit_creep("nonsense", [0.0], [0.0], [0.0])


@pytest.mark.process  # starts the CLI
def test_calibrate_cli_with_unknown_candidates_exits_2_without_a_traceback(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "polyforce_ros.cli", "calibrate", str(REPO / "bags" / "creep_5n.mcap"),
                           "--output", str(tmp_path / "m.yaml"), "--candidates", "nonsense"],
                          capture_output=True, text=True, cwd=REPO, timeout=120)
    assert proc.returncode == 2 and "nonsense" in proc.stderr and "Traceback" not in proc.stderr
