"""The command book across an engine lost and back: what was in flight is sent again under new
ids (never an id used before), and what the robot asks of an old id is answered by its new one."""

from __future__ import annotations

from brain.robot.commands import CommandBook
from protocol import Cancel, Cell, CommandState, CommandStatus, Navigate


def status(command: str, state: CommandState, tick: int = 1) -> CommandStatus:
    return CommandStatus(command=command, robot="robot", state=state, tick=tick)


def test_commands_in_flight_are_sent_again_under_new_ids() -> None:
    book = CommandBook("robot")
    done, walking, dropped = (book.send(Navigate(cell=Cell(c, 1))) for c in (1, 2, 3))
    book.cancel(dropped)  # c4: a cancel that the lost engine never answered
    book.drain()
    book.record(status(done, CommandState.SUCCEEDED))
    book.record(status(walking, CommandState.RUNNING))
    again = book.resend_in_flight()
    assert again == ["c5"], f"expected only the walk sent again, as c5; got {again}"
    (resent,) = book.drain()
    assert resent.action == Navigate(cell=Cell(2, 1)) and resent.id == "c5", resent
    assert book.final(dropped) and book.status(dropped).state is CommandState.CANCELLED, book.status(dropped)
    assert book.in_flight() == ["c5"], book.in_flight()
    assert not book.answered(walking), "the old id is answered only once its new one is"
    book.record(status("c5", CommandState.SUCCEEDED, tick=9))
    assert book.final(walking) and book.succeeded(book.status(walking)), book.status(walking)
    assert book.in_flight() == [], book.in_flight()


def test_a_cancel_of_an_old_id_cancels_its_new_one() -> None:
    book = CommandBook("robot")
    walking = book.send(Navigate(cell=Cell(1, 1)))
    book.resend_in_flight()
    book.drain()
    book.cancel(walking)
    (cancel,) = book.drain()
    assert cancel.action == Cancel(command="c2"), cancel
