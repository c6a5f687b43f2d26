"""The rating server: Python's threaded ``http.server``, on ``127.0.0.1`` unless told
otherwise, one link per participant (``/rate/ID?token=T``).

- A token per participant: an HMAC of their id under the study's secret (a file kept beside
  the answers, made on first use), so links stay valid when the server restarts; a wrong or
  missing token is refused (403) and nothing about the study is shown.
- Origin checks: an answer (``POST``) must come from the page's own origin (its ``Origin``
  header equal to ``http://`` + its ``Host``, or one of ``origins``); on loopback the ``Host``
  must be a loopback name (no DNS rebinding). Anything else is refused (403).
- Bounded (:mod:`.serving`): idle connections time out, at most so many at once, a client
  that goes away is one log line; a bad ``Content-Length`` is answered 400.
- The page records the participant's consent (``POST /rate/ID/consent?token=T``) before it
  shows a question; an answer is taken only after it, and only to the question the
  participant's page shows (:mod:`.progress`); else 409, saying which.
- Each answer is appended to the answers CSV whole and flushed before the reply
  (:class:`.answers.AnswerBook`); one the disk cannot take is answered 507 (500 for another
  write error), nothing of it kept; a page (re)load shows the participant's next unanswered
  question.
- A body that is not JSON, or nested too deep to decode, is answered 400.
"""

from __future__ import annotations

import errno
import hashlib
import hmac
import json
import logging
import random
import re
import secrets
import socket
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from http.server import BaseHTTPRequestHandler
from pathlib import Path
from typing import Any
from urllib.parse import parse_qs, quote, urlsplit

from bridge.errors import ConfigError
from bridge.recording import Trace

from .answers import AnswerBook
from .drawing import captions, frames, plan
from .page import page_state, render
from .progress import Progress
from .questions import Question, RatingStudy
from .serving import DEFAULT_LIMITS, BoundedHTTPServer, ServerLimits

log = logging.getLogger("toyroom.rating")

LOOPBACK_HOST = re.compile(r"^(localhost|127\.\d+\.\d+\.\d+|\[::1\])(:\d+)?$")
MAX_BODY = 64 * 1024
"""Largest answer accepted, in bytes."""
DISK_FULL = (errno.ENOSPC, errno.EFBIG, errno.EDQUOT)
"""Write errors answered 507 Insufficient Storage (the rest 500)."""


def read_or_make_secret(path: Path) -> bytes:
    """The study's secret in ``path``, made (32 random bytes, hex, mode 0600) when missing."""
    try:
        if not path.exists():
            path.parent.mkdir(parents=True, exist_ok=True)
            path.touch(mode=0o600)
            path.write_text(secrets.token_hex(32) + "\n", encoding="utf-8")
        secret = path.read_text(encoding="utf-8").strip()
    except OSError as err:
        raise ConfigError(f"cannot read or make the secret file {path}: {err.strerror}") from None
    if not secret:
        raise ConfigError(f"the secret file {path} is empty")
    return secret.encode()


def lan_address() -> str:
    """This machine's address on its network (for links when serving on every interface);
    a UDP socket is pointed at a private address, which sends nothing."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        try:
            probe.connect(("10.254.254.254", 1))
            return str(probe.getsockname()[0])
        except OSError:
            return socket.gethostname()


def token_for(secret: bytes, participant: str) -> str:
    """The token of ``participant``'s link (24 hex digits)."""
    return hmac.new(secret, participant.encode(), hashlib.sha256).hexdigest()[:24]


@dataclass(frozen=True)
class RatingSettings:
    """What the server serves: the study, its recordings (in the order the questions index
    them), the participants' ids, the answers CSV, the secret, and extra allowed origins."""

    study: RatingStudy
    traces: Sequence[Trace]
    participants: tuple[str, ...]
    answers: Path
    secret: bytes
    origins: tuple[str, ...] = ()


class RatingServer:
    """A running rating server on ``host:port`` (port 0: any free one); a context manager.

    Attributes:
        url: ``http://HOST:PORT`` it serves on.
    """

    def __init__(
        self,
        settings: RatingSettings,
        host: str = "127.0.0.1",
        port: int = 0,
        limits: ServerLimits = DEFAULT_LIMITS,
    ) -> None:
        self.settings = settings
        self.book = AnswerBook(settings.answers)
        self.progress = Progress()
        self.loopback = LOOPBACK_HOST.match(host) is not None
        self._pages: dict[tuple[int, int], tuple[list[dict[str, Any]], list[dict[str, Any]]]] = {}
        self._plans = [plan(t.info.scene) for t in settings.traces]
        self._lock = threading.Lock()
        handler = type("Handler", (_Handler,), {"rating": self})
        try:
            self._server = BoundedHTTPServer((host, port), handler, limits)
        except OSError as err:
            raise ConfigError(f"toyroom rate cannot listen on {host}:{port}: {err.strerror}") from None
        shown = lan_address() if host in ("0.0.0.0", "::") else host
        shown = f"[{shown}]" if ":" in shown else shown
        self.url = f"http://{shown}:{self._server.server_address[1]}"
        self._thread = threading.Thread(target=self._server.serve_forever, name="rating", daemon=True)
        self._thread.start()

    def link(self, participant: str) -> str:
        """``participant``'s link (with their token)."""
        token = token_for(self.settings.secret, participant)
        return f"{self.url}/rate/{quote(participant)}?token={token}"

    def order(self, participant: str) -> list[Question]:
        """The questions in the order ``participant`` gets them (shuffled per participant,
        the same on every load, when the study says so)."""
        questions = list(self.settings.study.questions)
        if self.settings.study.shuffle:
            random.Random(f"toyroom-rate:{participant}").shuffle(questions)
        return questions

    def next_question(self, participant: str) -> tuple[Question | None, int]:
        """The first question ``participant`` has not answered (``None``: all), and how many
        they have."""
        done = self.book.done(participant)
        left = [q for q in self.order(participant) if q.id not in done]
        return (left[0] if left else None), len(self.settings.study.questions) - len(left)

    def consented(self, participant: str) -> bool:
        """Whether ``participant`` agreed to take part: since this server started, or before
        (a saved answer says so)."""
        return self.progress.agreed(participant) or bool(self.book.done(participant))

    def agree(self, participant: str) -> tuple[int, str]:
        """Record ``participant``'s consent: ``(HTTP status, message)``."""
        if not self.progress.agreed(participant):
            log.info("%s agreed to take part", participant)
        self.progress.agree(participant)
        return 200, "consent recorded"

    def page(self, participant: str) -> str:
        """The page of ``participant``'s next question (recorded as the one they are shown)."""
        question, answered = self.next_question(participant)
        self.progress.show(participant, question.id if question else None)
        token = token_for(self.settings.secret, participant)
        base = f"/rate/{quote(participant)}"
        where: dict[str, Any] = {
            "answered": answered,
            "consented": self.consented(participant),
            "answer_url": f"{base}/answer?token={token}",
            "consent_url": f"{base}/consent?token={token}",
        }
        if question is None:
            state = page_state(None, plan=None, frames=[], **where)
        else:
            key = (question.recording, question.show_until)
            with self._lock:
                if key not in self._pages:
                    trace, rate = self.settings.traces[key[0]], self.settings.study.replay_rate
                    self._pages[key] = (frames(trace, key[1], rate), captions(trace, key[1]))
            state = page_state(
                question,
                plan=self._plans[question.recording],
                frames=self._pages[key][0],
                captions=self._pages[key][1],
                rate=self.settings.study.replay_rate,
                tick_seconds=self.settings.traces[key[0]].info.tick_seconds,
                **where,
            )
        return render(self.settings.study, participant, question, state)

    def answer(self, participant: str, body: dict[str, Any]) -> tuple[int, str]:
        """Save ``participant``'s answer ``{"question": ID, "values": {TARGET: 0-1}}``:
        ``(HTTP status, message)``: 400 for a malformed answer, 409 for one answered already,
        before consent or to a question the participant's page does not show, 507 (500) when
        it cannot be written."""
        qid, values = body.get("question"), body.get("values")
        question = next((q for q in self.settings.study.questions if q.id == qid), None)
        if question is None:
            return 400, f"no question {qid!r} in this study"
        if not isinstance(values, dict) or set(values) != set(question.targets):
            return 400, f"expected a value for each of {', '.join(question.targets)}"
        numbers = list(values.values())
        if not all(isinstance(v, int | float) and not isinstance(v, bool) and 0 <= v <= 1 for v in numbers):
            return 400, "every value must be a number from 0 to 1"
        if (refused := self._out_of_turn(participant, question.id)) is not None:
            return 409, refused
        try:
            if not self.book.add(participant, question, values):
                return 409, f"question {qid} was answered already"
        except OSError as err:
            log.error(
                "%s's answer to %s was not saved: %s: %s", participant, qid, self.book.path, err.strerror
            )
            status = 507 if err.errno in DISK_FULL else 500
            return status, (
                f"the server cannot write the answers ({err.strerror}); nothing of this answer was "
                "kept: tell the experimenter, then press Next again"
            )
        log.info("%s answered %s", participant, qid)
        return 200, "saved"

    def _out_of_turn(self, participant: str, qid: str) -> str | None:
        """Why ``participant`` may not answer ``qid`` now (answered already, no consent, not the
        question their page shows), or ``None``."""
        if qid in self.book.done(participant):
            return f"question {qid} was answered already"
        if not self.consented(participant):
            return f"refused: {participant} has not agreed to take part yet: open the link and agree first"
        shown = self.progress.shown(participant)
        if shown != qid:
            now = f"question {shown}" if shown else "no question"
            return (
                f"refused: question {qid} is not the one {participant}'s page shows ({now}): reload the page"
            )
        return None

    def close(self) -> None:
        """Stop serving (every answer is on disk already)."""
        self._server.shutdown()
        self._server.server_close()
        self._thread.join(timeout=5.0)

    def __enter__(self) -> RatingServer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class _Handler(BaseHTTPRequestHandler):
    """One request: a participant's page (``GET /rate/ID?token=T``) or answer (``POST
    /rate/ID/answer?token=T``)."""

    rating: RatingServer
    server_version = "toyroom-rate"

    def log_message(self, format: str, *args: Any) -> None:
        log.debug("%s %s", self.address_string(), format % args)

    def _reply(self, status: int, text: str, kind: str = "text/plain; charset=utf-8") -> None:
        data = text.encode("utf-8")
        self.send_response(status)
        self.send_header("Content-Type", kind)
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Frame-Options", "DENY")
        self.end_headers()
        self.wfile.write(data)

    def _participant(self, suffix: str) -> str | None:
        """The participant of a request to ``/rate/ID`` + ``suffix`` whose token is right
        and whose host is allowed; else replies 403 or 404 and returns ``None``."""
        host = self.headers.get("Host", "")
        if self.rating.loopback and not LOOPBACK_HOST.match(host):
            self._reply(403, f"refused: host {host!r} is not this server's loopback address")
            return None
        parts = urlsplit(self.path)
        match = re.fullmatch(r"/rate/([A-Za-z0-9_.-]+)" + re.escape(suffix), parts.path)
        if match is None or match.group(1) not in self.rating.settings.participants:
            self._reply(404, "no such page: use the link you were given")
            return None
        token = parse_qs(parts.query).get("token", [""])[0]
        expected = token_for(self.rating.settings.secret, match.group(1))
        if not hmac.compare_digest(token.encode(), expected.encode()):
            self._reply(403, "refused: wrong or missing token for this link")
            return None
        return match.group(1)

    def do_GET(self) -> None:  # noqa: N802 - http.server's name
        participant = self._participant("")
        if participant is not None:
            self._reply(200, self.rating.page(participant), "text/html; charset=utf-8")

    def do_POST(self) -> None:  # noqa: N802 - http.server's name
        """An answer (``/rate/ID/answer``) or the participant's consent (``/rate/ID/consent``,
        whose JSON object, ``{"consent": true}`` from the page, is read and not looked into),
        from the page's origin."""
        consent = urlsplit(self.path).path.endswith("/consent")
        participant = self._participant("/consent" if consent else "/answer")
        if participant is None:
            return
        origin = self.headers.get("Origin")
        allowed = {f"http://{self.headers.get('Host', '')}", *self.rating.settings.origins}
        if origin not in allowed:
            self._reply(403, f"refused: origin {origin!r} is not this page's")
            return
        body = self._body()  # read whole either way: a socket closed unread may reset the reply
        if body is not None:
            self._reply(
                *(self.rating.agree(participant) if consent else self.rating.answer(participant, body))
            )

    def _body(self) -> dict[str, Any] | None:
        """The answer's JSON object; else replies 400 and returns ``None``."""
        length = self._length()
        if length is None:
            return None
        try:
            body = json.loads(self.rfile.read(length))
        except (ValueError, UnicodeDecodeError):
            self._reply(400, "the body is not JSON")
            return None
        except RecursionError:
            self._reply(400, "the body is not an answer: JSON nested too deep to decode")
            return None
        if not isinstance(body, dict):
            self._reply(400, "expected a JSON object")
            return None
        return body

    def _length(self) -> int | None:
        """The body's length in bytes from ``Content-Length``; else replies 400 (and logs one
        line) and returns ``None``."""
        raw = self.headers.get("Content-Length")
        text = (raw or "").strip()
        length = int(text) if re.fullmatch(r"[0-9]{1,9}", text) else -1
        if 0 < length <= MAX_BODY:
            return length
        problem = "no Content-Length" if raw is None else f"Content-Length {raw!r}"
        log.warning("%s: refused an answer with %s", self.address_string(), problem)
        self._reply(
            400, f"expected a JSON body of 1 to {MAX_BODY} bytes (a Content-Length in bytes), got {problem}"
        )
        return None
