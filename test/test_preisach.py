"""Preisach operator (seed 001): forward, identification, closest-match and continuous inverses."""
import numpy as np
import pytest

from polyforce_ros.physics.preisach import PreisachModel, hysteresis_error_percent, identify


def random_model(n=40, seed=0, u_max=4.5):
    rng = np.random.default_rng(seed)
    i, j = np.tril_indices(n)
    # a smooth bump near the diagonal (narrow loops weigh most), strictly positive
    density = np.zeros((n, n))
    density[i, j] = (0.2 + rng.uniform(0, 1, i.size)) * np.exp(-((i - j) / (0.3 * n)) ** 2) * 1e-3
    return PreisachModel(0.0, u_max, density, offset=0.5)


def increasing_triangles(u_max=4.5, n_amp=40, points=200):
    """Seed 001's identification input: triangles of 40 evenly spaced amplitudes up to u_max."""
    parts = []
    for a in np.linspace(0, u_max, n_amp + 1)[1:]:  # exactly the level edges, so every relay row switches
        parts += [np.linspace(0, a, points, endpoint=False), np.linspace(a, 0, points, endpoint=False)]
    return np.concatenate(parts + [[0.0]])


def grip_profile(n=4000, seed=1, u_max=4.5):
    rng = np.random.default_rng(seed)
    knots = np.concatenate(([0], rng.uniform(0.1, 0.95, 12) * u_max, [0]))
    return np.interp(np.linspace(0, knots.size - 1, n), np.arange(knots.size), knots)


def test_sizes_and_batch_equals_stream():
    model = random_model()
    assert model.n_hysterons == 820
    u = grip_profile()
    stream = model.stream()
    np.testing.assert_allclose([stream.forward(x) for x in u], model.forward(u), rtol=0, atol=1e-12)


def test_wiping_out_property_and_hysteresis():
    model = random_model()
    up_down = np.concatenate([np.linspace(0, 4.5, 500), np.linspace(4.5, 0, 500)])
    y = model.forward(up_down)
    assert hysteresis_error_percent(up_down, y) > 1.0  # a real loop
    # A minor loop inside a larger excursion is wiped out by it: the output after the
    # large excursion does not depend on the minor loop.
    with_minor = np.concatenate([np.linspace(0, 2, 50), np.linspace(2, 1, 50), np.linspace(1, 4.5, 100), [3.0]])
    without = np.concatenate([np.linspace(0, 4.5, 200), [3.0]])
    assert model.forward(with_minor)[-1] == pytest.approx(model.forward(without)[-1], abs=1e-12)


def test_identification_recovers_the_response_on_unseen_input():
    truth = random_model(seed=3)
    u_train = increasing_triangles()
    model = identify(u_train, truth.forward(u_train), n_levels=40, u_min=0.0, u_max=4.5)
    u_test = grip_profile(seed=5)
    err = model.forward(u_test) - truth.forward(u_test)
    assert np.abs(err).max() < 1e-6 * np.ptp(truth.forward(u_test)) + 1e-9
    assert np.all(model.density >= 0)


def test_continuous_operator_agrees_with_relays_at_edges_and_inverts_exactly():
    model = random_model(seed=4)
    u = grip_profile(seed=6)
    on_edges = model.edges[np.round((u - model.u_min) / model.level_step).astype(int)]
    cont = model.stream(continuous=True)
    np.testing.assert_allclose([cont.forward(x) for x in on_edges], model.forward(on_edges), atol=1e-12)
    fwd, inv = model.stream(continuous=True), model.stream(continuous=True)
    y = [fwd.forward(x) for x in u]
    back = np.array([inv.inverse(v) for v in y])
    np.testing.assert_allclose(back[1:], u[1:], atol=1e-9)
    assert np.all(np.abs(np.diff(y)) < 0.05 * np.ptp(y))  # continuous: no jumps at reversals


def test_discrete_cma_undoes_discrete_forward_within_one_level():
    model = random_model(seed=7)
    fwd, inv = model.stream(), model.stream()
    u = grip_profile(seed=8)
    y = [fwd.forward(x) for x in u]
    back = np.array([inv.inverse(v) for v in y])
    assert np.abs(back - u).max() <= model.level_step + 1e-12  # the quantisation bound


def test_round_trip_through_yaml_mapping_and_validation():
    model = random_model(n=6)
    again = PreisachModel.from_dict(model.to_dict())
    np.testing.assert_array_equal(again.density, model.density)
    bad = model.to_dict()
    bad["density"] = bad["density"][:-1]
    with pytest.raises(ValueError, match="needs 21 values"):
        PreisachModel.from_dict(bad)
    with pytest.raises(ValueError, match="non-negative"):
        PreisachModel(0.0, 1.0, -np.eye(3))
