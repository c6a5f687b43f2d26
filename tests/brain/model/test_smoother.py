"""Forward filtering and forward-backward smoothing against brute-force enumeration of every
hidden path (to 1e-9), in the generative story of a step: the preference switches over the
pause before the step (``H_t``), then the decision is drawn under the new preference
(``L_t``), then the belief takes in the new percept (``T_t``)."""

from __future__ import annotations

import itertools

import msgspec
import numpy as np
import pytest
from scenes import tiny_scene, tiny_state

from brain.model.inference import HmmStep, forward, hazard_matrix, smooth
from brain.model.modes import CARRY, PURSUE, dropped_carry
from brain.model.person.exactperson import ExactModel
from brain.model.person.gradedperson import GradedModel
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker


def enumerate_marginals(prior: np.ndarray, steps: list[HmmStep]) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Exact filtered and smoothed marginals by summing the joint over all hidden paths."""
    W, D = prior.shape
    states = [(w, d) for w in range(W) for d in range(D)]
    T = len(steps)
    smoothed = [np.zeros((W, D)) for _ in range(T)]
    filtered_num = [np.zeros((W, D)) for _ in range(T)]
    for path in itertools.product(range(len(states)), repeat=T + 1):
        z = [states[i] for i in path]  # z[0] is the state before the first step
        p = prior[z[0]]
        weights = []
        for t, step in enumerate(steps):
            (w0, d0), (w1, d1) = z[t], z[t + 1]
            lik = 1.0 if step.likelihood is None else step.likelihood[w0, d1]  # under the new d
            p *= hazard_matrix(D, step.switch)[d0, d1] * lik * step.transition[w1, w0]
            weights.append(p)
        for t in range(T):
            smoothed[t][z[t + 1]] += p
        # filtered: the prefix joint up to step t, summed over paths (each prefix counted once
        # per continuation, so divide by the number of continuations)
        for t in range(T):
            filtered_num[t][z[t + 1]] += weights[t] / (W * D) ** (T - 1 - t)
    return [f / f.sum() for f in filtered_num], [s / s.sum() for s in smoothed]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_chain(seed: int) -> None:
    rng = np.random.default_rng(seed)
    W, D, T = 3, 2, 4
    steps = []
    for t in range(T):
        transition = rng.random((W, W))
        transition /= transition.sum(axis=0, keepdims=True)
        likelihood = None if t == 1 else rng.random((W, D))
        steps.append(
            HmmStep(tick=t, transition=transition, likelihood=likelihood, switch=[0.0, 0.1, 0.3, 0.05][t])
        )
    prior = rng.random((W, D))
    prior /= prior.sum()
    want_filtered, want_smoothed = enumerate_marginals(prior, steps)
    for t, (got, want) in enumerate(zip(forward(prior, steps), want_filtered, strict=True)):
        assert np.allclose(got, want, atol=1e-9, rtol=0), f"step {t}: filtered {got}, enumeration {want}"
    for t, (got, want) in enumerate(zip(smooth(prior, steps), want_smoothed, strict=True)):
        assert np.allclose(got, want, atol=1e-9, rtol=0), f"step {t}: smoothed {got}, enumeration {want}"


def tiny_trace(settings: ModelSettings) -> MindTracker:
    """A person comes in from outside, walks to B, takes the ball, walks to A and plays."""
    tracker = MindTracker(tiny_scene(), settings)
    route = [
        ((4, 0), False),
        ((3, 0), False),
        ((2, 0), False),
        ((2, 0), True),
        ((1, 0), True),
        ((0, 0), True),
    ]
    for tick, (cell, holding) in enumerate(route):
        from protocol import Event, EventKind

        events = ()
        if tick == 3:
            events = (
                Event(
                    episode=1,
                    tick=tick,
                    time=tick * 0.7,
                    kind=EventKind.TAKE,
                    actor="p",
                    item="ball",
                    location="B",
                ),
            )
        tracker.observe(tiny_state(tick, cell, None if holding else "B", holding), events)
    return tracker


def carry_trace(settings: ModelSettings) -> MindTracker:
    """A person at B takes the ball, carries it to A and drops it there (five steps)."""
    from protocol import Event, EventKind

    tracker = MindTracker(tiny_scene(), settings)
    route = [((2, 0), "B", False), ((2, 0), None, True), ((1, 0), None, True), ((0, 0), None, True)]
    route.append(((0, 0), "A", False))
    kinds = {1: (EventKind.TAKE, "B"), 4: (EventKind.DROP, "A")}
    for tick, (cell, ball_at, holding) in enumerate(route):
        events = ()
        if tick in kinds:
            kind, location = kinds[tick]
            events = (
                Event(
                    episode=1,
                    tick=tick,
                    time=tick * 0.7,
                    kind=kind,
                    actor="p",
                    item="ball",
                    location=location,
                ),
            )
        tracker.observe(tiny_state(tick, cell, ball_at, holding), events)
    steps = tracker.tracks["p"].steps
    assert steps[-1].decision is not None and dropped_carry(steps[-1].decision, 1) == 0, (
        "the last step drops the ball"
    )
    return tracker


def test_real_trace_of_the_tiny_scene() -> None:
    tracker = tiny_trace(ModelSettings(belief_model="point"))
    records = tracker.tracks["p"].steps
    assert len(records) == 6 and [s.likelihood is None for s in records] == [True] + [False] * 5
    exact = tracker.person_model
    assert isinstance(exact, ExactModel), "the tiny scene fits the exact model"
    steps = [exact.hmm_step(r) for r in records]
    prior = exact.prior()
    _, want_smoothed = enumerate_marginals(prior, steps[:4])
    for t, (got, want) in enumerate(zip(smooth(prior, steps[:4]), want_smoothed, strict=True)):
        assert np.allclose(got, want, atol=1e-9, rtol=0), f"step {t}: smoothed {got}, enumeration {want}"
    final = tracker.online("p")
    assert final is not None and final.preference[0] > 0.9, (
        "walking in, taking the ball and carrying it to play"
    )


def test_graded_smoothing_equals_enumeration() -> None:
    """The graded model's forward-backward over (hypothesis g, preference d) against the
    sum over every preference sequence (D**T of them; each hypothesis's belief, and so each
    step's QMDP likelihood, is fixed by g), with a hazard high enough to matter."""
    tracker = tiny_trace(ModelSettings(hazard=0.3, errand_per_s=0.0, carry_per_s=0.0))
    graded = tracker.person_model
    assert isinstance(graded, GradedModel), "the default is the graded model"
    records = tracker.tracks["p"].steps
    beliefs, likelihoods = graded.initial.copy(), []
    for record in records:  # L_t(g, d) of the preference after step t's switch
        likelihood = graded.decision_likelihood(beliefs, record)
        likelihoods.append(np.ones_like(graded.prior()) if likelihood is None else likelihood)
        beliefs = graded.revise(beliefs, record)
    G, D = graded.prior().shape
    T = len(records)
    want = np.zeros((T, G, D))
    for start in range(D):
        for path in itertools.product(range(D), repeat=T):  # d_t: step t's, after its switch
            weight = graded.prior()[:, start].copy()  # P(g, d_0 = start)
            before = start
            for t, record in enumerate(records):
                weight = (
                    weight * hazard_matrix(D, record.switch)[before, path[t]] * likelihoods[t][:, path[t]]
                )
                before = path[t]
            for t in range(T):
                want[t, :, path[t]] += weight
    want /= want.sum(axis=(1, 2), keepdims=True)
    got = graded.smoothed(records, tracker.tracks["p"].estimates)
    for t, est in enumerate(got):
        assert est.hypotheses is not None
        assert np.allclose(est.preference, want[t].sum(axis=0), atol=1e-9), (
            f"step {t}: preference {est.preference}, enumeration {want[t].sum(axis=0)}"
        )
        assert np.allclose(est.hypotheses[0], want[t].sum(axis=1), atol=1e-9), f"step {t}: hypothesis weights"


@pytest.mark.parametrize("belief_model", ["point", "graded"])
def test_log_evidence_is_the_unnormalised_forward_pass(belief_model: str) -> None:
    """``log_evidence`` (the sum of the filter's log normalisers) equals the log of the total
    mass of the forward pass run without normalising: log P(all decisions)."""
    tracker = tiny_trace(
        ModelSettings(belief_model=belief_model, hazard=0.3, errand_per_s=0.0, carry_per_s=0.0)
    )
    records = tracker.tracks["p"].steps
    person = tracker.person_model
    alpha = person.prior()
    if isinstance(person, ExactModel):
        for record in records:
            step = person.hmm_step(record)
            if step.switch > 0:  # the pause before the step, then its decision
                alpha = alpha @ hazard_matrix(alpha.shape[1], step.switch)
            weighted = alpha if step.likelihood is None else alpha * step.likelihood
            alpha = step.transition @ weighted
    else:
        assert isinstance(person, GradedModel)
        beliefs = person.initial.copy()
        for record in records:
            likelihood = person.decision_likelihood(beliefs, record)
            if record.switch > 0:  # the pause before the step, then its decision
                alpha = alpha @ hazard_matrix(alpha.shape[1], record.switch)
            alpha = alpha if likelihood is None else alpha * likelihood
            beliefs = person.revise(beliefs, record)
    want = float(np.log(alpha.sum()))
    got = tracker.log_evidence("p")
    assert got == pytest.approx(want, abs=1e-9), f"log evidence {got}, unnormalised forward pass {want}"
    assert got < 0.0


def old_order(prior: np.ndarray, steps: list[HmmStep]) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Filtered and smoothed posteriors with the switch applied AFTER the decision's
    likelihood (``alpha_t = T_t @ (L_t * alpha_{t-1}) @ H_t``): the order before the fix, as a
    reference the test shows the fix departs from."""
    alphas, alpha = [], prior
    for step in steps:
        alpha = step.transition @ (alpha if step.likelihood is None else alpha * step.likelihood)
        alpha = alpha @ hazard_matrix(alpha.shape[1], step.switch) if step.switch > 0 else alpha
        alphas.append(alpha / alpha.sum())
    beta, out = np.ones_like(prior), [np.empty(0)] * len(steps)
    for t in range(len(steps) - 1, -1, -1):
        out[t] = alphas[t] * beta / (alphas[t] * beta).sum()
        step = steps[t]
        mixed = beta @ hazard_matrix(beta.shape[1], step.switch).T if step.switch > 0 else beta
        back = step.transition.T @ mixed
        beta = back * step.likelihood if step.likelihood is not None else back
        beta = beta / beta.sum()
    return alphas, out


@pytest.mark.parametrize("belief_model", ["point", "graded"])
def test_the_decision_ending_a_long_pause_is_judged_under_the_switched_desire(belief_model: str) -> None:
    """Seen at (1,0), the person walks out (ticks 1-3: ``out``, sure), stands outside 35 s (no
    wait is read outside; 50 decision times, a switch of 1 - 0.99**50 = 0.39 at hazard 0.01),
    then walks back in towards the ball at A (ticks 5-8). The pause's switch comes before the
    decision that ends it: the online estimate right after walking in already favours the
    ball (it was 0.52 with the switch after the likelihood), and the smoothed estimate on
    arriving outside (tick 3, before the pause) keeps ``out`` (it gave the ball 0.69)."""
    settings = ModelSettings(belief_model=belief_model, hazard=0.01, errand_per_s=0.0, carry_per_s=0.0)
    tracker = MindTracker(tiny_scene(), settings)
    pause = 35.0
    path = [(1, 0), (2, 0), (3, 0), (4, 0), (4, 0), (3, 0), (2, 0), (1, 0), (0, 0)]
    times = [0.7 * i for i in range(4)] + [2.1 + pause / 2] + [2.1 + pause + 0.7 * i for i in range(4)]
    for tick, (cell, time) in enumerate(zip(path, times, strict=True)):
        state = tiny_state(tick, cell, "A")
        tracker.observe(msgspec.structs.replace(state, time=round(time, 9)), ())
    records = tracker.tracks["p"].steps
    ticks = [r.tick for r in records]
    assert ticks == [0, 1, 2, 3, 5, 6, 7, 8], f"expected steps at ticks 0-3 and 5-8, got {ticks}"
    entering, before = ticks.index(5), ticks.index(3)
    switch = records[entering].switch
    assert switch == pytest.approx(1 - 0.99**50, abs=0.01), (
        f"expected the pause's switch 1 - 0.99**50 = {1 - 0.99**50:.3f} on walking in, got {switch:.3f}"
    )
    online = [e.preference for e in tracker.tracks["p"].estimates]  # [ball, out]
    smoothed = [e.preference for e in tracker.smoothed("p")]
    person = tracker.person_model
    if isinstance(person, GradedModel):  # a hypothesis's belief is fixed by g: no transition
        beliefs, steps = person.initial.copy(), []
        for record in records:
            likelihood = person.decision_likelihood(beliefs, record)
            steps.append(HmmStep(record.tick, np.eye(len(beliefs)), likelihood, record.switch))
            beliefs = person.revise(beliefs, record)
    else:
        assert isinstance(person, ExactModel)
        steps = [person.hmm_step(r) for r in records]
    old_online, old_smoothed = ([p.sum(axis=0) for p in ps] for ps in old_order(person.prior(), steps))
    assert online[before][1] > 0.95, f"expected out sure before the pause, got P(out) {online[before][1]:.3f}"
    assert online[entering][0] > 0.9, (
        f"expected walking in after the pause to favour the ball online (P > 0.9), got "
        f"{online[entering][0]:.3f} (switch after the likelihood: {old_online[entering][0]:.3f})"
    )
    assert online[entering][0] > old_online[entering][0] + 0.3, (
        f"expected the online P(ball) on walking in well above the old order's "
        f"{old_online[entering][0]:.3f}, got {online[entering][0]:.3f}"
    )
    assert smoothed[before][1] > 0.95, (
        f"expected the smoothed estimate before the pause to keep out (P > 0.95), got "
        f"{smoothed[before][1]:.3f} (switch after the likelihood: {old_smoothed[before][1]:.3f})"
    )
    assert old_smoothed[before][1] < 0.5, (
        f"the old order should have given the tick before the pause the new desire, got P(out) "
        f"{old_smoothed[before][1]:.3f}"
    )
    assert smoothed[entering][0] > 0.99, (
        f"expected the ball after walking in, got {smoothed[entering][0]:.3f}"
    )


def test_smoothing_with_modes_equals_enumeration() -> None:
    """With modes (:mod:`brain.model.modes`), forward-backward over (g, u, m) against the sum
    over every sequence of (desire, mode) ((U M)**T of them), rates high enough to matter; a
    Drop of the item carried ends its carry (the mode reported after it is ``pursue``)."""
    settings = ModelSettings(hazard=0.3, errand_per_s=0.5, carry_per_s=0.4, resume_per_s=0.8)
    tracker = carry_trace(settings)
    graded = tracker.person_model
    assert isinstance(graded, GradedModel) and graded.rates is not None, "the tiny scene has an outside"
    records = tracker.tracks["p"].steps
    beliefs, steps = graded.initial.copy(), []
    for record in records:
        steps.append(graded.mode_step(beliefs, record))
        beliefs = graded.revise(beliefs, record)
    G, U = graded.prior().shape
    T, M = len(records), len(graded.rates.stationary)
    start = graded.prior()[:, :, None] * graded.rates.stationary[None, None, :]
    want = np.zeros((T, G, U, M))
    for u0, m0 in itertools.product(range(U), range(M)):
        for path in itertools.product(itertools.product(range(U), range(M)), repeat=T):
            weight, (u, m), reported = start[:, u0, m0].copy(), (u0, m0), []
            for t, step in enumerate(steps):
                nu, nm = path[t]
                weight = weight * hazard_matrix(U, step.switch)[u, nu] * step.transition[m, nm]
                if step.likelihood is not None:
                    weight = weight * np.broadcast_to(step.likelihood, (G, U, M))[:, nu, nm]
                ended = dropped_carry(step.decision, M - CARRY)
                u, m = nu, (PURSUE if ended is not None and nm == CARRY + ended else nm)
                reported.append((u, m))
            for t in range(T):
                want[t, :, reported[t][0], reported[t][1]] += weight
    want /= want.sum(axis=(1, 2, 3), keepdims=True)
    got = graded.smoothed(records, tracker.tracks["p"].estimates)
    for t, est in enumerate(got):
        assert est.mode is not None
        assert np.allclose(est.preference, want[t].sum(axis=(0, 2)), atol=1e-9), (
            f"step {t}: preference {est.preference}, enumeration {want[t].sum(axis=(0, 2))}"
        )
        assert np.allclose(est.mode, want[t].sum(axis=(0, 1)), atol=1e-9), (
            f"step {t}: mode {est.mode}, enumeration {want[t].sum(axis=(0, 1))}"
        )


def test_log_evidence_with_modes_is_the_unnormalised_forward_pass() -> None:
    """With modes, ``log_evidence`` is the log of the forward pass over (g, u, m) run
    without normalising."""
    settings = ModelSettings(hazard=0.3, errand_per_s=0.5, carry_per_s=0.4, resume_per_s=0.8)
    tracker = carry_trace(settings)
    person = tracker.person_model
    assert isinstance(person, GradedModel) and person.rates is not None
    joint = person.prior()[:, :, None] * person.rates.stationary[None, None, :]
    beliefs = person.initial.copy()
    for record in tracker.tracks["p"].steps:
        step = person.mode_step(beliefs, record)
        redraw = hazard_matrix(joint.shape[1], step.switch)
        joint = np.einsum("gum,ux,mn->gxn", joint, redraw, step.transition)
        if step.likelihood is not None:
            joint = joint * step.likelihood
        ended = dropped_carry(step.decision, joint.shape[2] - CARRY)
        if ended is not None:
            joint[:, :, PURSUE] += joint[:, :, CARRY + ended]
            joint[:, :, CARRY + ended] = 0.0
        beliefs = person.revise(beliefs, record)
    want = float(np.log(joint.sum()))
    got = tracker.log_evidence("p")
    assert got == pytest.approx(want, abs=1e-9), f"log evidence {got}, unnormalised forward pass {want}"
