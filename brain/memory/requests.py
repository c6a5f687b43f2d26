"""Forgetting a person in a memory file that a running brain holds.

A brain holds its memory file for as long as it runs (:mod:`.opening`), so ``toyroom memory
forget`` cannot open it then. It leaves a request instead, one small file in the folder
beside the memory (``FILE.forget/``, :func:`folder`), and waits for the answer. The running
brain looks for requests at every tick (:class:`~brain.memory.keeper.MemoryKeeper`): it
removes the person's rows and their bytes (:meth:`~brain.memory.store.MemoryStore.forget`),
saves nothing more of them for the rest of its life, and answers (how many rows went, or why
it could not). A request no brain answered (it stopped first) is carried out by the next
process that opens the file for writing: a brain, or ``toyroom memory forget``
(:func:`carry_out`).

The request names the person in plain text until it is answered; the answer file is removed
by the ``forget`` that reads it.
"""

from __future__ import annotations

import os
import uuid
from collections.abc import Callable
from pathlib import Path

import msgspec

from bridge.recording.atomic import write_bytes

from ..errors import MemoryRequestError
from .store import MemoryStore

REQUEST, ANSWER = ".request", ".answer"


class ForgetRequest(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """Forget ``person`` in ``household`` (``None``: the one household that holds them)."""

    person: str
    household: str | None = None


class ForgetAnswer(msgspec.Struct, frozen=True):
    """What became of a :class:`ForgetRequest`: the household it was carried out in and the rows
    removed, or ``error`` (one line); ``tick``: the engine tick of the brain that carried it
    out (``None``: no brain was running). It does not repeat the person's name."""

    household: str | None = None
    removed: int = 0
    error: str = ""
    tick: int | None = None


def folder(memory: Path) -> Path:
    """Where requests to forget in ``memory`` wait: ``FILE.forget/`` beside it."""
    return memory.with_name(memory.name + ".forget")


def ask(memory: Path, request: ForgetRequest) -> Path:
    """Leave ``request`` for whoever holds ``memory``; the request's file."""
    where = folder(memory)
    where.mkdir(mode=0o700, exist_ok=True)
    path = where / f"{uuid.uuid4().hex}{REQUEST}"
    write_bytes(path, msgspec.json.encode(request))  # whole, or not there at all
    return path


def answer_of(request: Path) -> ForgetAnswer | None:
    """The answer to the request at ``request`` (its file then removed), or ``None`` yet."""
    path = request.with_suffix(ANSWER)
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        return None
    path.unlink(missing_ok=True)
    _tidy(request.parent)
    return msgspec.json.decode(data, type=ForgetAnswer)


def withdraw(request: Path) -> ForgetAnswer | None:
    """Take back the request at ``request``: ``None``, or its answer when it was carried out
    first."""
    request.unlink(missing_ok=True)
    answer = answer_of(request)
    if answer is None:
        _tidy(request.parent)
    return answer


def pending(memory: Path) -> list[Path]:
    """The requests waiting at ``memory``, oldest first."""
    try:
        found = [p for p in folder(memory).iterdir() if p.suffix == REQUEST and p.name[0] != "."]
    except (FileNotFoundError, NotADirectoryError):
        return []
    return sorted(found, key=lambda p: (p.stat().st_mtime_ns, p.name))


def serve(memory: Path, carry: Callable[[ForgetRequest], ForgetAnswer]) -> list[ForgetAnswer]:
    """Carry out every request waiting at ``memory`` with ``carry``, answer each and remove
    it; the answers (an unreadable request is answered with an error)."""
    answers = []
    for path in pending(memory):
        try:
            answer = carry(msgspec.json.decode(path.read_bytes(), type=ForgetRequest))
        except (msgspec.DecodeError, msgspec.ValidationError) as err:
            answer = ForgetAnswer(error=f"forget request {path.name} is not one: {err}")
        except FileNotFoundError:  # answered by another process meanwhile
            continue
        write_bytes(path.with_suffix(ANSWER), msgspec.json.encode(answer))
        path.unlink(missing_ok=True)
        answers.append(answer)
    return answers


def carry_out(store: MemoryStore) -> list[ForgetAnswer]:
    """Carry out the requests waiting at ``store``'s file, by a process that holds it with no
    scene of its own (``toyroom memory forget``, a brain before its first day)."""

    def carry(request: ForgetRequest) -> ForgetAnswer:
        try:
            home = store.household_of(request.person, request.household)
            return ForgetAnswer(home, store.forget(request.person, home))
        except MemoryRequestError as err:
            return ForgetAnswer(request.household, error=str(err))

    return serve(store.path, carry)


def _tidy(where: Path) -> None:
    """Remove the requests' folder once nothing waits in it."""
    try:
        os.rmdir(where)
    except OSError:
        pass
