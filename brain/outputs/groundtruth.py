"""The paper's ground truth per scenario step, as data (``brain/groundtruth/<scenario>.toml``),
for drawing beside the model's estimates. Analysis data only: inference never reads it."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field

from protocol.bundled import bundled_dir

GROUND_TRUTH_DIR = bundled_dir("brain", "groundtruth")


@dataclass(frozen=True)
class TruthStep:
    """Ground truth at one labelled step: belief per item over locations, preference over
    items, and ``believed_by``: per other person, where they believe this agent believes each
    item is (nested beliefs)."""

    label: str
    belief: dict[str, dict[str, float]]
    preference: dict[str, float]
    believed_by: dict[str, dict[str, dict[str, float]]] = field(default_factory=dict)


@dataclass(frozen=True)
class GroundTruth:
    """A scenario's ground truth for one agent: its labelled steps in order."""

    scenario: str
    agent: str
    steps: tuple[TruthStep, ...]

    def at(self, label: str) -> TruthStep | None:
        return next((s for s in self.steps if s.label == label), None)


def load_ground_truth(scenario: str) -> GroundTruth | None:
    """The ground truth of a scenario, or ``None`` when there is none."""
    path = GROUND_TRUTH_DIR / f"{scenario}.toml"
    if not path.exists():
        return None
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    steps = tuple(
        TruthStep(
            label=str(step["label"]),
            belief={item: dict(dist) for item, dist in step.get("belief", {}).items()},
            preference=dict(step.get("preference", {})),
            believed_by={
                person: {item: dict(dist) for item, dist in items.items()}
                for person, items in step.get("believed_by", {}).items()
            },
        )
        for step in data.get("steps", [])
    )
    return GroundTruth(scenario=data["scenario"], agent=data["agent"], steps=steps)
