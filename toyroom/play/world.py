"""One participant's world: the engine (``python -m sim2d --realtime RATE --puppet PERSON``)
and the brain (``python -m brain``), each its own process, on a world of the participant's
own, recorded to ``OUT/<participant>.mcap``.

Started when the participant's page first connects: the engine starts and is paused at once,
the recorder records from its handshake, the brain resets it to the scenario (a fresh
episode at tick 0), and the world waits for the participant to read the study's instructions
(and consent, when it asks) and press Start; it then runs while the page is connected (paused
while it is not: a reload resumes where it was). A second tab on the same link takes over:
the first is told and its keys are no longer taken. The world ends when the study's goal is
met or its time limit passes (:mod:`.goal`; the brain is stopped and writes its outputs for
the ticks so far), when the episode does (the brain finishes), or, incomplete, when the page
stays away for the grace period, a node fails or the server stops. The ``toyroom.play``
metadata record says which (``outcome``: :class:`protocol.StudyOutcome`), and why.
"""

from __future__ import annotations

import logging
import subprocess
import threading
import time
from collections.abc import Callable
from typing import Any

import msgspec

from bridge.bridge import Bridge
from bridge.processes import node_command, start_node, stop_nodes, wait_for_engine
from bridge.pubsub import Received
from protocol import (
    AgentKind,
    CommandStatus,
    ControlReply,
    EngineInfo,
    Event,
    Pause,
    Resume,
    RobotCommand,
    Say,
    SayTopic,
    State,
    StudyOutcome,
)

from .config import PlayConfig
from .goal import GoalWatch
from .keys import command_for, digit_keys
from .palette import person_colours
from .recording import PlayRecorder
from .sight import Memory, Sight
from .speech import Speech, in_earshot

log = logging.getLogger("toyroom.play")
STOP_GRACE = 120.0
"""Seconds a stopped brain may take to write its outputs before it is killed."""

Send = Callable[[dict[str, Any]], None]


TAKEN_OVER = "This game continues in another tab or window; this one no longer sends your keys."


class PlayWorld:
    """One participant's world (see the module docstring). Thread-safe."""

    def __init__(self, config: PlayConfig, participant: str, world: str) -> None:
        self.config = config
        self.participant = participant
        self.world = world
        self.folder = config.out / participant
        self.recording = config.out / f"{participant}.mcap"
        self.nodes: list[subprocess.Popen[bytes]] = []
        self.bridge: Bridge | None = None
        self.recorder: PlayRecorder | None = None
        self.sight: Sight | None = None
        self.speech: Speech | None = None
        self.memory = Memory()
        self.layout: dict[str, Any] | None = None
        self.view: dict[str, Any] = {"type": "status", "status": "starting"}
        self.ended: str | None = None
        """Why the world ended (``None`` while it runs)."""
        self.outcome: StudyOutcome | None = None
        """How the world ended (``None`` while it runs); the study's own terms, while it runs,
        are :attr:`goal`'s."""
        self.goal = GoalWatch(config.study, config.person)
        self.started = False
        """The participant has pressed Start (after the instructions, and consent if asked)."""
        self.tick_seconds = 0.1
        """The engine's tick, in seconds (from its handshake)."""
        self._send: Send | None = None
        self._lock = threading.RLock()
        self._closed = threading.Event()
        """Set once :meth:`end` has closed the recording, the nodes and the session: a second
        caller (the server stopping while a page's end is under way) waits for it, so the
        process never exits with the Zenoh session half closed (a native abort: 'FATAL:
        exception not rethrown', exit -6)."""
        self._seq = 0
        self._state: State | None = None
        self._episode = -1
        self._left_at: float | None = time.monotonic()
        self._pressed = (0.0, 0.0, 0.0)
        """``(base, last, when)``: what a page's key times are counted from (0 for the first
        page; a reload's from the last key's time plus the seconds since it), the last key's
        time so counted, and the monotonic clock then: a recording's key times never run back."""
        self._publisher: Any = None
        self.ready = threading.Event()
        """The brain has reset the engine to a fresh episode: the world may run."""

    # ----- the page -------------------------------------------------------------------

    def attach(self, send: Send) -> None:
        """A page connected: send it the map and the view, and run the world once started. A
        reload replaces the page before; a second tab takes over, and the first is told."""
        with self._lock:
            before = self._send
            if before is not None or self._left_at is not None:  # not the first page
                _, last, when = self._pressed
                self._pressed = (last + (time.monotonic() - when if when else 0.0), last, when)
            self._send, self._left_at = send, None
            if before is not None:
                self._tell(before, {"type": "taken_over", "message": TAKEN_OVER})
            for message in (self.layout, self._heard_view()):
                if message is not None:
                    send(message)
        if self.ready.is_set() and self.started:
            self._control(Resume())

    def begin(self, send: Send) -> bool:
        """The participant pressed Start on page ``send`` (having consented, if the study asks):
        the clock starts. Whether it did (not from a page that was taken over)."""
        with self._lock:
            if send is not self._send or self.ended is not None:
                return False
            self.started = True
            self._push(self._heard_view())
        if self.ready.is_set():
            self._control(Resume())
        return True

    def current(self, send: Send) -> bool:
        """Whether ``send`` is the page that drives the world (not one taken over)."""
        return send is self._send

    @staticmethod
    def _tell(send: Send, message: dict[str, Any]) -> None:
        try:
            send(message)
        except Exception:  # a page closing as we send  # noqa: BLE001
            log.debug("telling a page failed", exc_info=True)

    def detach(self, send: Send) -> None:
        """The page ``send`` went away: pause the world (unless another page took its place)."""
        with self._lock:
            if self._send is not send:
                return
            self._send, self._left_at = None, time.monotonic()
        self._control(Pause())

    def abandoned(self) -> bool:
        """Whether the page has been away longer than the grace period."""
        left = self._left_at
        return left is not None and self.ended is None and time.monotonic() - left > self.config.grace

    def _push(self, message: dict[str, Any]) -> None:
        send = self._send
        if send is not None:
            self._tell(send, message)

    def key(self, key: str, pressed: float) -> bool:
        """The participant pressed ``key`` at ``pressed`` s (page time, counted on from the pages
        before: :attr:`_pressed`): publish its command; whether the key meant one."""
        layout = self.layout or {}
        with self._lock:
            base, last, _ = self._pressed
            pressed = max(base + pressed, last)
            self._pressed = (base, pressed, time.monotonic())
            goto = layout.get("goto_keys", {})
            answers = self._answer_keys()
            command = command_for(
                key, self.config.person, self._seq, goto, pressed, self.participant, answers
            )
            if command is None or self._publisher is None or self.ended is not None or not self.started:
                return False
            self._seq += 1
            self._publisher.put(command)
        return True

    def _answer_keys(self) -> dict[str, str] | None:
        """The digit keys that name items while the robot asks what the person is looking for
        (``None``: no such question is open)."""
        speech = self.speech
        question = speech.heard.question if speech is not None else None
        if speech is None or question is None or question["kind"] != "what":
            return None
        return speech.answers

    # ----- the world --------------------------------------------------------------------

    def start(self) -> None:
        """Start the engine (paused), the recorder and the brain.

        Raises:
            BridgeError: the engine did not answer its handshake.
        """
        config = self.config
        self.folder.mkdir(parents=True, exist_ok=True)
        engine_args = [
            "--scenario",
            config.scenario,
            "--realtime",
            str(config.rate),
            "--puppet",
            config.person,
        ]
        engine_args += ["--seed", str(config.seed), "--log-level", config.log_level]
        engine = start_node(
            node_command("sim2d", self.world, config.settings, *engine_args),
            self.folder / "engine.log",
            group=True,
        )
        self.nodes.append(engine)
        self.bridge = bridge = Bridge(self.world, config.settings)
        info = wait_for_engine(bridge, engine)
        if info is None:
            raise RuntimeError(
                f"the engine exited (status {engine.returncode}); see {self.folder / 'engine.log'}"
            )
        self._control(Pause())
        self._setup(bridge, info)
        brain_args = ["--scenario", config.scenario, "--seed", str(config.seed), "--out", str(self.folder)]
        brain_args += ["--timeout", "0", "--log-level", config.log_level]
        brain = node_command("brain", self.world, config.settings, *brain_args)
        self.nodes.append(start_node(brain, self.folder / "brain.log", group=True))
        deadline = time.monotonic() + 120.0
        while not self.ready.wait(0.2):
            problem = self.failed()
            if problem is not None or time.monotonic() > deadline:
                raise RuntimeError(problem or "the brain did not reset the engine within 120 s")
        if self._send is not None and self.started:
            self._control(Resume())

    def _setup(self, bridge: Bridge, info: EngineInfo) -> None:
        person = self.config.person
        self.tick_seconds = info.tick_seconds
        self.sight = sight = Sight(info.scene, person)
        if person not in {a.id for a in info.scene.agents}:
            raise RuntimeError(f"scenario '{info.scenario}' has no person '{person}'")
        regions = {r.id: r.name or r.id for r in info.scene.regions}
        places = {loc.id: regions.get(loc.region, loc.region) for loc in info.scene.locations}
        self.speech = Speech(person, sight.names, places, digit_keys([i.id for i in info.scene.items]))
        people = [a.id for a in info.scene.agents if a.kind is AgentKind.PERSON]
        with self._lock:
            self.layout = sight.layout(self.participant) | {
                "world": self.world,
                "scenario": info.scenario,
                "study": msgspec.to_builtins(self.config.study) if self.config.study else None,
                "colours": person_colours(people),
            }
            if self._send is not None:
                self._send(self.layout)
        self.recorder = PlayRecorder(bridge, self.recording, info, self._metadata)
        self._publisher = bridge.publisher(bridge.keys.person_command(person))
        bridge.subscribe(bridge.keys.state, self._on_state, expected=State)
        bridge.subscribe(bridge.keys.events, self._on_event, expected=Event)
        bridge.subscribe(bridge.keys.command(), self._on_command, expected=RobotCommand)
        bridge.subscribe(bridge.keys.status(), self._on_status, expected=CommandStatus)

    def _control(self, request: Pause | Resume) -> None:
        bridge = self.bridge
        if bridge is None or self.ended is not None:
            return
        try:
            bridge.query(bridge.keys.control, request, ControlReply, timeout=5.0)
        except Exception as err:  # noqa: BLE001 - the engine is gone: the monitor ends the world
            log.warning("%s: %s failed: %s", self.participant, type(request).__name__.lower(), err)

    def _on_state(self, state: State, _: Received) -> None:
        sight = self.sight
        if sight is None or state.episode < self._episode:
            return
        with self._lock:
            if state.episode > self._episode:  # the brain's reset: a fresh episode, a fresh memory
                self._episode, self.memory = state.episode, Memory()
                if state.episode >= 1:
                    self.ready.set()
            self._state = state
            if self.ready.is_set() and self.started:
                self.goal.on_state(state)
            self.view = sight.look(state, self.memory)
            self._push(self._heard_view())

    def _on_event(self, event: Event, _: Received) -> None:
        if event.episode == self._episode and self.ready.is_set():
            with self._lock:
                self.goal.on_event(event)

    def _heard_view(self) -> dict[str, Any]:
        heard = self.speech.heard if self.speech is not None else None
        view = dict(self.view)
        if heard is not None:
            view["speech"] = heard.lines[-6:]
            view["question"] = heard.question
        view["ended"] = self.ended
        view["started"] = self.started
        return view

    def _on_command(self, command: RobotCommand, _: Received) -> None:
        if self.speech is not None:
            with self._lock:
                self.speech.on_command(command)

    def _on_status(self, status: CommandStatus, _: Received) -> None:
        speech, state = self.speech, self._state
        if speech is None or state is None:
            return
        with self._lock:
            command = speech.commands.get(status.command)
            hears = in_earshot(state, self.config.person, status.robot)
            changed = speech.on_status(status, state.tick, hears, self._holds(status.robot))
            action = command.action if command is not None else None
            told = (
                isinstance(action, Say)
                and action.topic is SayTopic.LOCATION
                and action.person == self.config.person
            )
            if changed and told and isinstance(action, Say):
                for item in action.told:
                    self.memory.note(item.item, item.location, state.tick)
            if changed:
                self._push(self._heard_view())

    def _holds(self, robot: str) -> str | None:
        state = self._state
        agent = next((a for a in state.agents if a.id == robot), None) if state is not None else None
        return agent.holding if agent is not None else None

    def _metadata(self) -> dict[str, str]:
        state = self._state
        return {
            "participant": self.participant,
            "person": self.config.person,
            "scenario": self.config.scenario,
            "world": self.world,
            "rate": str(self.config.rate),
            "complete": "true" if self.complete else "false",
            "outcome": (self.outcome or StudyOutcome.INCOMPLETE).value if self.ended else "",
            "reason": self.ended or "",
            "last_tick": str(state.tick if state is not None else -1),
        }

    @property
    def complete(self) -> bool:
        """Whether the world ended whole (at its goal, its limit or its end), not cut short."""
        return self.outcome is not None and self.outcome is not StudyOutcome.INCOMPLETE

    @property
    def world_time(self) -> float | None:
        """The engine time of the last state (s), ``None`` before the first."""
        state = self._state
        return state.time if state is not None else None

    def brain_finished(self) -> bool:
        """Whether the brain has exited with success (the episode is over)."""
        return len(self.nodes) > 1 and self.nodes[1].poll() == 0

    def failed(self) -> str | None:
        """Why a node has failed, if one has."""
        for name, node in zip(("engine", "brain"), self.nodes, strict=False):
            status = node.poll()
            if status is not None and not (name == "brain" and status == 0):
                return f"the {name} exited with status {status} (see {self.folder / (name + '.log')})"
        return None

    def end(self, reason: str, outcome: StudyOutcome = StudyOutcome.INCOMPLETE) -> None:
        """Stop the nodes (the brain writes its outputs so far) and finish the recording, with
        ``outcome`` (complete unless ``incomplete``) and ``reason``; the page is told. Safe to
        call twice."""
        with self._lock:
            first = self.ended is None
            if first:
                self.ended, self.outcome = reason, outcome
        if not first:  # another thread is ending it: wait until it has (the server may be exiting)
            self._closed.wait(timeout=60.0)
            return
        try:
            if self.recorder is not None:
                self.recorder.close()
            stop_nodes(list(reversed(self.nodes)), grace=STOP_GRACE)
            if self.bridge is not None:
                self.bridge.close()
        finally:
            self._closed.set()
        self._push(self._heard_view() | {"type": "view"})
