"""What every participant's world of a ``toyroom play`` server runs."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from bridge.session import SessionSettings
from protocol import Study


@dataclass(frozen=True)
class PlayConfig:
    """What every participant's world runs."""

    scenario: str
    person: str
    out: Path
    rate: float = 1.0
    seed: int = 0
    grace: float = 60.0
    """Seconds a closed page may take to come back before the world ends, incomplete."""
    log_level: str = "WARNING"
    settings: SessionSettings = field(default_factory=SessionSettings)
    study: Study | None = None
    """The scenario's ``[study]``: instructions, goal, time limit, consent."""
