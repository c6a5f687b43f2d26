"""``nested_belief_accuracy`` and its first-order baseline on a hand-built tick."""

from __future__ import annotations

from protocol import AgentMind, ItemBelief, Mind, NestedBelief, Prob, TrueMind, Truth
from toyroom.evaluation.metrics import Counts
from toyroom.evaluation.nestedscore import score_nested


def belief(item: str, **p: float) -> ItemBelief:
    return ItemBelief(item=item, locations=tuple(Prob(loc, v) for loc, v in p.items()))


def test_one_nested_belief_that_differs_is_scored_by_hand() -> None:
    # A thinks B thinks: ball at L1 (B believes L2: counted), cup at L3 (B believes L3 too: not
    # counted); B thinks A thinks the ball at L2 but A is unsure of it (not counted).
    a = TrueMind(
        agent="A",
        beliefs=(belief("ball", L1=0.5, L2=0.5), belief("cup", L3=1.0)),
        preference="ball",
        nested=(NestedBelief("B", (belief("ball", L1=1.0), belief("cup", L3=1.0))),),
    )
    b = TrueMind(
        agent="B",
        beliefs=(belief("ball", L2=1.0), belief("cup", L3=1.0)),
        preference="cup",
        nested=(NestedBelief("A", (belief("ball", L2=1.0), belief("cup", L3=1.0))),),
    )
    truth = Truth(episode=0, tick=5, agents=(a, b))

    def agent(name: str, own: tuple[ItemBelief, ...], nested: tuple[NestedBelief, ...]) -> AgentMind:
        return AgentMind(agent=name, beliefs=own, preference=(Prob("ball", 1.0),), nested_beliefs=nested)

    mind = Mind(
        episode=0,
        tick=5,
        agents=(
            agent(
                "A",
                (belief("ball", L1=0.5, L2=0.5),),
                (NestedBelief("B", (belief("ball", L1=0.7, L2=0.3),)),),
            ),
            agent("B", (belief("ball", L1=0.1, L2=0.9),), ()),
        ),
    )
    counts = Counts()
    score_nested(mind, truth, counts)
    got = (counts.nested_n, counts.nested_right, counts.nested_first_right)
    assert got == (1, 1, 0), f"expected 1 pair scored, nested right, first-order wrong; got {got}"
    scores = counts.nested_scores()
    assert scores == {"nested_belief_accuracy": 1.0, "nested_first_order_accuracy": 0.0, "nested_gain": 1.0}
