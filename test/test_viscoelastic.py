"""Viscoelastic models: the paper's numbers, J/G consistency, round trips, long records."""
import numpy as np
import pytest

from polyforce_ros.physics.viscoelastic import (
    MODEL_TYPES,
    PAPER_BURGERS,
    BackwardState,
    Burgers,
    Elastic,
    ForwardState,
    KelvinVoigt,
    Maxwell,
    StreamingCompensator,
    Zener,
    Zener2,
    Burgers2,
    Zener3,
    Burgers3,
    compensate,
    simulate_deformation,
)

MODELS = [Maxwell(3.0, 400.0), KelvinVoigt(3.2, 40.0), Zener(4.8, 10.0, 85.12), PAPER_BURGERS,
          Zener2(4.8, 10.0, 85.12, 20.0, 30.0), Burgers2(4.8, 10.0, 4627.94, 85.12, 20.0, 30.0),
          Zener3(4.8, 10.0, 15.0, 20.0, 300.0, 12.0, 1200.0),
          Burgers3(4.8, 10.0, 4627.94, 15.0, 20.0, 300.0, 12.0, 1200.0)]


def test_paper_eq5_to_eq9_at_printed_precision():
    rel = PAPER_BURGERS.relaxation()
    (a1, a2), (r1, r2) = rel.a_n_per_v, rel.r_per_s
    assert round(a1, 2) == 3.23
    assert round(a2, 2) == 1.57
    assert round(r1 * 1e3, 3) == 0.699
    assert round(PAPER_BURGERS.retardation_time_s(), 2) == 8.51
    assert round(PAPER_BURGERS.static_gain_v_per_n(), 2) == 0.31
    assert rel.g0_n_per_v == pytest.approx(4.8)
    # The paper prints r2 = 0.173 1/s; eq. 8 with the printed eq. 5 gives 0.1742.
    # No parameter set within eq. 5's rounding reproduces 0.173 together with the
    # other printed values, so this is the paper's own rounding slip: we hold r2
    # to 1 % (docs/evaluation.md).
    assert r2 == pytest.approx(0.173, rel=0.01)
    assert r2 == pytest.approx(0.17421, abs=5e-5)


@pytest.mark.parametrize("model", [m for m in MODELS if m.kind in ("maxwell", "zener", "burgers")], ids=lambda m: m.kind)
def test_generic_relaxation_from_compliance_equals_the_closed_forms(model):
    """The residue route used by the two-Kelvin models gives eq. 7-8's G(t) for the classic ones."""
    from polyforce_ros.physics.viscoelastic.models import _relaxation_from_compliance

    closed, generic = model.relaxation(), _relaxation_from_compliance(model.compliance())
    assert generic.g_inf_n_per_v == pytest.approx(closed.g_inf_n_per_v, rel=1e-12, abs=1e-12)
    np.testing.assert_allclose(generic.r_per_s, closed.r_per_s, rtol=1e-12)
    np.testing.assert_allclose(generic.a_n_per_v, closed.a_n_per_v, rtol=1e-12)


@pytest.mark.parametrize("model", MODELS, ids=lambda m: m.kind)
def test_relaxation_is_the_inverse_of_creep_in_laplace_domain(model):
    """s G(s) * s J(s) = 1 for every s: G really is the relaxation modulus of J."""
    c, g = model.compliance(), model.relaxation()
    for s in (1e-4, 0.01, 0.3, 5.0, 300.0):
        s_j = c.j0_v_per_n + sum(ci / (1 + ti * s) for ci, ti in zip(c.c_v_per_n, c.tau_s)) + c.fluidity_v_per_n_s / s
        s_g = g.g_inf_n_per_v + sum(a * s / (s + r) for a, r in zip(g.a_n_per_v, g.r_per_s)) + g.eta_impulse_n_s_per_v * s
        assert s_j * s_g == pytest.approx(1.0, rel=1e-12)


def test_burgers_initial_conditions_of_relaxation():
    g = PAPER_BURGERS.relaxation()
    k1, eta1, eta2 = 4.8, 4627.94, 85.12
    dg0 = -sum(a * r for a, r in zip(g.a_n_per_v, g.r_per_s))
    assert g(0.0) == pytest.approx(k1)
    assert dg0 == pytest.approx(-k1**2 * (1 / eta1 + 1 / eta2))


@pytest.mark.parametrize("model", MODELS, ids=lambda m: m.kind)
def test_constant_force_from_t0_gives_creep_compliance_exactly(model):
    t = 5.0 + np.arange(0, 200, 0.01)
    gamma = simulate_deformation(model, t, np.full(t.size, 5.0))
    np.testing.assert_allclose(gamma, 5.0 * model.creep_compliance(t - t[0]), rtol=1e-11, atol=1e-14)


def test_burgers_creep_compliance_is_eq4():
    t = np.array([0.0, 1.0, 8.512, 100.0, 3600.0])
    k1, k2, eta1, eta2 = 4.8, 10.0, 4627.94, 85.12
    expected = 1 / k1 + (1 - np.exp(-k2 * t / eta2)) / k2 + t / eta1
    np.testing.assert_allclose(PAPER_BURGERS.creep_compliance(t), expected, rtol=1e-14)


def loading(t, rng):
    """Steps (with 20 ms ramps), a sawtooth, a sine and a random walk: a hard mixed history."""
    steps = np.interp(t, [0, 10, 10.02, 40, 40.02, 200], [0, 0, 5, 5, 1, 1])
    saw = 2.0 * np.abs(((t / 20.0) % 2) - 1)
    walk = np.cumsum(rng.normal(0, 0.01, t.size))
    return steps + saw + 0.5 * np.sin(2 * np.pi * 1.3 * t) + walk


#: Noise-free round trip bound (N): discretisation only (forward is exact for
#: piecewise-linear force, backward for piecewise-linear deformation).
ROUND_TRIP_BOUND_N = 1e-6


@pytest.mark.parametrize("model", [m for m in MODELS if m.kind != "kelvin"], ids=lambda m: m.kind)
def test_compensation_recovers_force(model):
    rng = np.random.default_rng(3)
    t = np.arange(0, 200, 1e-3)
    f = loading(t, rng)
    gamma = simulate_deformation(model, t, f)
    assert np.abs(compensate(model, t, gamma) - f).max() < ROUND_TRIP_BOUND_N
    # With bridge noise of sigma volts the error is the instantaneous gain times the noise.
    sigma = 1e-3
    noisy = gamma + rng.normal(0, sigma, t.size)
    err = compensate(model, t, noisy) - f
    g0 = model.relaxation().g0_n_per_v
    assert np.abs(err).max() < 6 * g0 * sigma
    assert abs(err.mean()) < 0.1 * g0 * sigma  # no drift from the noise


def test_kelvin_voigt_compensation_on_smooth_force():
    model = KelvinVoigt(3.2, 40.0)
    t = np.arange(0, 60, 1e-3)
    f = 2 + np.sin(2 * np.pi * 0.2 * t) - np.cos(2 * np.pi * 0.05 * t)
    est = compensate(model, t, simulate_deformation(model, t, f))
    assert np.abs(est[1:] - f[1:]).max() < 1e-3  # first-order slope: O(h) error


@pytest.mark.parametrize("model", MODELS, ids=lambda m: m.kind)
def test_streaming_equals_batch(model):
    rng = np.random.default_rng(4)
    t = np.cumsum(rng.uniform(0.0008, 0.0012, 20000))
    t[8000:] += 10.0  # gap
    t[12000] = t[11999]  # duplicate stamp
    f = loading(t, rng)
    gamma = simulate_deformation(model, t, f) + rng.normal(0, 1e-3, t.size)
    batch = compensate(model, t, gamma)
    comp = StreamingCompensator(model)
    stream = np.array([comp.step(ti, gi) for ti, gi in zip(t, gamma)])
    scale = np.abs(batch).max()
    assert np.abs(stream - batch).max() <= 1e-9 * scale


@pytest.mark.parametrize("model", MODELS + [Burgers(4.8, 10.0, 46.0, 0.9)], ids=lambda m: m.kind)
def test_uniform_fast_path_equals_streaming_in_blocks_that_switch_paths(model):
    """Uniform stamps take the single-pass cascade, others the modal recursion.

    Blocks alternate between the two (a jittered block in the middle), so the
    history is handed across in both directions; the streaming compensator,
    which has only the modal form, is the reference.
    """
    rng = np.random.default_rng(7)
    t = np.arange(30000) * 1e-3
    t[10000:15000] += rng.uniform(0, 3e-4, 5000)  # jitter: this block is not uniform
    f = loading(t, rng)
    gamma = simulate_deformation(model, t, f) + rng.normal(0, 1e-3, t.size)
    comp = StreamingCompensator(model)
    stream = np.array([comp.step(ti, gi) for ti, gi in zip(t, gamma)])
    state = BackwardState(model)
    blocks = [compensate(model, t[a:b], gamma[a:b], state=state)
              for a, b in [(0, 1), (1, 10000), (10000, 15000), (15000, 15001), (15001, 30000)]]
    whole = compensate(model, t[:10000], gamma[:10000])
    scale = np.abs(stream).max()
    assert np.abs(np.concatenate(blocks) - stream).max() <= 1e-9 * scale
    assert np.abs(whole - stream[:10000]).max() <= 1e-9 * scale


def test_uniform_fast_path_falls_back_when_its_factorisation_does_not_apply():
    """A negative relaxation coefficient (not a passive sensor) has no cascade here;
    compensate must then still be the modal recursion, not an error."""
    from polyforce_ros.physics.viscoelastic import RelaxationModulus
    from polyforce_ros.physics.viscoelastic.superposition import _UniformCascade

    passive = PAPER_BURGERS.relaxation()
    assert _UniformCascade.build(passive, 1e-3) is not None
    odd = RelaxationModulus(1.0, (2.0, -0.5), passive.r_per_s)
    assert _UniformCascade.build(odd, 1e-3) is None


def test_streaming_rejects_backwards_time_without_corrupting_state():
    comp, ref = StreamingCompensator(PAPER_BURGERS), StreamingCompensator(PAPER_BURGERS)
    for i in range(100):
        comp.step(i * 1e-3, 0.3)
        ref.step(i * 1e-3, 0.3)
    assert comp.step(0.05, 9.0) is None
    assert comp.step(0.1, 0.3) == ref.step(0.1, 0.3)


@pytest.mark.parametrize("model", [Elastic(3.0), KelvinVoigt(3.2, 40.0), PAPER_BURGERS], ids=lambda m: m.kind)
def test_streaming_backwards_time_and_duplicate_stamps_for_models_with_and_without_exponentials(model):
    """A stamp before the previous one gives None and changes nothing, also for models whose relaxation
    has no exponential (only the Kelvin-Voigt slope remembers time there); an equal stamp is a
    zero-length step: no slope term, the history does not move."""
    comp, ref = StreamingCompensator(model), StreamingCompensator(model)
    for i in range(10):
        comp.step(i * 1e-3, 0.1 * i)
        ref.step(i * 1e-3, 0.1 * i)
    assert comp.step(0.005, 9.0) is None
    assert comp.last_time_s == ref.last_time_s == 9 * 1e-3
    assert comp.step(0.01, 1.5) == ref.step(0.01, 1.5)
    history = ref.step(0.01, 0.0)  # the history term alone (no slope at a repeated stamp)
    assert comp.step(0.01, 2.0) == pytest.approx(model.relaxation().g0_n_per_v * 2.0 + history, rel=1e-12, abs=1e-12)
    assert comp.last_time_s == 0.01


def test_gap_in_stamps_is_handled_as_linear_deformation_between_samples():
    """A 10 s gap: the state after it equals a densely sampled record of the same linear bridge."""
    model = PAPER_BURGERS
    t_dense = np.arange(0, 30, 1e-3)
    gamma = np.interp(t_dense, [0, 5, 15, 30], [0.0, 1.0, 1.5, 1.5])
    keep = (t_dense <= 5.0) | (t_dense >= 15.0)
    dense = compensate(model, t_dense, gamma)
    gapped = compensate(model, t_dense[keep], gamma[keep])
    np.testing.assert_allclose(gapped, dense[keep], rtol=1e-9, atol=1e-9)


def test_24_hours_at_1khz_error_at_end_equals_error_at_start():
    """86.4 million samples in 1-hour chunks: no overflow, no accumulation of error.

    By linearity the compensated force is the noise-free round trip plus the
    compensated noise: the round trip is checked over all 24 hours, the noise
    response in the first and the last hour.
    """
    model = PAPER_BURGERS
    fwd, bwd = ForwardState(model), BackwardState(model)
    rng = np.random.default_rng(5)
    round_trip_max, noise_rms = [], []
    for hour in range(24):
        t = hour * 3600.0 + np.arange(3_600_000) / 1000.0
        f = 2.0 + 1.5 * np.sin(2 * np.pi * 0.5 * t) + np.sign(np.sin(2 * np.pi * t / 600.0))
        est = compensate(model, t, simulate_deformation(model, t, f, state=fwd), state=bwd)
        assert np.all(np.isfinite(est))
        round_trip_max.append(np.abs(est - f).max())
        if hour in (0, 23):
            noise_force = compensate(model, t, rng.normal(0, 1e-3, t.size))
            noise_rms.append(np.sqrt(np.mean(noise_force**2)))
    assert max(round_trip_max) < ROUND_TRIP_BOUND_N
    assert round_trip_max[-1] < 10 * round_trip_max[0] + 1e-8  # no growth beyond rounding
    assert noise_rms[1] == pytest.approx(noise_rms[0], rel=0.02)


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), float("inf")])
def test_absurd_parameters_are_rejected(bad):
    with pytest.raises(ValueError, match="k1_n_per_v"):
        Burgers(bad, 10.0, 4000.0, 80.0)
    with pytest.raises(TypeError):
        Zener("4.8", 10.0, 85.0)


@pytest.mark.parametrize("kind", sorted(MODEL_TYPES))
def test_each_model_type_declares_the_shape_of_its_compliance(kind):
    """``shape`` (Kelvin units, instantaneous spring, free dashpot), read by fitting and diagnosis, is the model's own."""
    cls = MODEL_TYPES[kind]
    rng = np.random.default_rng(len(kind))
    for _ in range(5):
        c = cls.from_vector(rng.uniform(1.0, 50.0, len(cls.parameter_names()))).compliance()
        assert cls.shape == (len(c.tau_s), c.j0_v_per_n > 0, c.fluidity_v_per_n_s > 0)
