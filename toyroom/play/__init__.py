"""``toyroom play``: a participant plays one person of a scenario in the browser, in a world of
their own (the engine in real time with that person as a puppet, the brain and the robot as
in ``toyroom run``), recorded to MCAP with every key press.

The server and the page (:mod:`.server`, ``page.html``), one participant's world
(:mod:`.world`), what the person sees (:mod:`.sight`) and hears (:mod:`.speech`), and the
keyboard (:mod:`.keys`).
"""

from .config import PlayConfig
from .keys import INSTRUCTIONS, command_for, digit_keys
from .recording import PLAY_METADATA, PlayRecorder, complete_only, play_metadata
from .server import PlayServer, parse_listen
from .sight import Memory, Sight, goto_keys
from .speech import Heard, Speech
from .timing import held_rate
from .world import PlayWorld

__all__ = [
    "INSTRUCTIONS",
    "PLAY_METADATA",
    "Heard",
    "Memory",
    "PlayConfig",
    "PlayRecorder",
    "PlayServer",
    "PlayWorld",
    "Sight",
    "Speech",
    "command_for",
    "complete_only",
    "digit_keys",
    "goto_keys",
    "held_rate",
    "parse_listen",
    "play_metadata",
]
