"""The robot tree's branches, one builder each, in the paper's priority order (Section IV.B):
inform, swap, put back, then go home (:func:`build_tree` puts them together)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import py_trees

from protocol import Ask, Cell, Give, GridCell, Navigate, Pick, Place, Policy, Request, Say, SayTopic, Told

from ..robotsettings import ROBOT_POLICIES, RobotSettings
from .behaviours import Act, FindTask, GoHome, TaskBranch
from .benefit import cell_distances
from .choice import look_chosen, question_chosen
from .context import RobotContext, Skip, Step
from .deception import benefit_inform, benefit_put_back, inform_or_deceived, put_back_unless_deceived
from .situation import (
    AskWhat,
    Finder,
    Inform,
    Look,
    Occupied,
    PutBack,
    announce_tasks,
    occupied_tasks,
    tidy_tasks,
)


def navigate_timeout(settings: RobotSettings) -> float:
    """How long a walk may take (s)."""
    return settings.navigate_timeout


def answer_timeout(settings: RobotSettings) -> float:
    """How long a give, request or ask may take: it waits for a person's answer (s)."""
    return settings.answer_timeout


def _inform(ctx: RobotContext) -> Inform:
    assert isinstance(ctx.task, Inform)
    return ctx.task


def _tell_now(ctx: RobotContext) -> Inform:
    """The inform task as its finder sees it now: the same task, with the items worth naming
    with it as they are at this tick (a tell's ``also`` is chosen afresh), or as chosen."""
    task = _inform(ctx)
    if ctx.finder is not None and ctx.snapshot is not None:
        now = next((t for t in ctx.finder(ctx.snapshot, ctx.settings) if t == task), None)
        if isinstance(now, Inform):
            return now
    return task


def _say_where(task: Inform) -> Say:
    """The ``say`` of an inform: the task's item, and the others it names (``also``)."""
    also = tuple(Told(item, location) for item, location in task.also)
    return Say(person=task.person, item=task.item, topic=SayTopic.LOCATION, location=task.location, also=also)


def _said(task: Inform) -> str:
    """An inform's sentence, e.g. ``"A1, the ball is at S1, the skate at P1."``."""
    rest = "".join(f", the {item} at {location}" for item, location in task.also)
    return f"{task.person}, the {task.item} is at {task.location}{rest}."


def _occupied(ctx: RobotContext) -> Occupied:
    assert isinstance(ctx.task, Occupied)
    return ctx.task


def _put_back(ctx: RobotContext) -> PutBack:
    assert isinstance(ctx.task, PutBack)
    return ctx.task


def go_to(
    name: str, where: Callable[[RobotContext], GridCell | None], ns: str, *, guarded: bool = False
) -> Act:
    """Walk next to the cell ``where`` says (``guarded``: give up once the task is not needed)."""
    return Act(name, lambda c: c.near(where(c)), ns, timeout=navigate_timeout, guarded=guarded)


def with_offer(make: Callable[[RobotContext, str], Step]) -> Callable[[RobotContext], Step]:
    """An action maker for the swap's offered item (nothing to do when there is no offer)."""

    def build(ctx: RobotContext) -> Step:
        offer = _occupied(ctx).offer
        return Skip.SKIP if offer is None else make(ctx, offer)

    return build


def offer_spot(ctx: RobotContext, offer: str) -> Step:
    """A walk to where the offered item is (nothing to do when the robot already holds it)."""
    assert ctx.snapshot is not None
    location, holder = ctx.snapshot.item(offer)
    if ctx.holding(ctx.robot) == offer:
        return Skip.SKIP
    return ctx.near(ctx.location_cell(location) if location else ctx.cell_of(holder or ""))


def inform_branch(ns: str, finder: Finder = inform_or_deceived) -> TaskBranch:
    """A person heads for an item that is not where they believe: tell them where it is
    (``finder``: who is told what; the ``announce`` policy tells everyone of every move)."""
    say = Act("say where it is", lambda c: _say_where(_tell_now(c)), ns, says=lambda c: _said(_tell_now(c)))
    questions: dict[object, str] = {announce_tasks: "moved?", benefit_inform: "worth telling?"}
    question = questions.get(finder, "false belief?")
    return TaskBranch(
        "inform",
        ns,
        [
            FindTask(question, "inform", finder, ns),
            go_to("go to the person", lambda c: c.cell_of(_inform(c).person), ns, guarded=True),
            say,
        ],
    )


def _swap_question(ctx: RobotContext) -> str:
    task = _occupied(ctx)
    offer = f" for the {task.offer}?" if task.offer else "?"
    return f"{task.holder}, would you give the {task.item} to {task.person}" + offer


def _holder_cell(ctx: RobotContext) -> GridCell | None:
    return ctx.cell_of(_occupied(ctx).holder)


def _person_cell(ctx: RobotContext) -> GridCell | None:
    return ctx.cell_of(_occupied(ctx).person)


def swap_accepted(ns: str) -> py_trees.composites.Sequence:
    """Ask the holder for a swap; on yes, bring the item to the person and the offer back."""
    ask = Act(
        "ask for a swap",
        lambda c: Request(person=_occupied(c).holder, item=_occupied(c).item, offer=_occupied(c).offer),
        ns,
        says=_swap_question,
        timeout=answer_timeout,
    )
    pick = Act(
        "pick the offer", with_offer(lambda c, o: Skip.SKIP if c.holding(c.robot) == o else Pick(item=o)), ns
    )
    back = Act(
        "go to the holder", with_offer(lambda c, o: c.near(_holder_cell(c))), ns, timeout=navigate_timeout
    )
    children: list[py_trees.behaviour.Behaviour] = [
        go_to("go to the holder", _holder_cell, ns),
        ask,
        go_to("go to the person", _person_cell, ns),
        Act("give the item", lambda c: Give(person=_occupied(c).person), ns, timeout=answer_timeout),
        Act("go to the offer", with_offer(offer_spot), ns, timeout=navigate_timeout),
        pick,
        back,
        Act(
            "give the offer",
            with_offer(lambda c, o: Give(person=_occupied(c).holder)),
            ns,
            timeout=answer_timeout,
        ),
    ]
    return py_trees.composites.Sequence("swap accepted", memory=True, children=children)


def _say_free(ctx: RobotContext, offer: str) -> Step:
    """Tell the person where the free, offered item is (nothing to say when it is carried)."""
    location = ctx.snapshot.item(offer)[0] if ctx.snapshot is not None else None
    if not location:
        return Skip.SKIP
    return Say(person=_occupied(ctx).person, item=offer, topic=SayTopic.LOCATION, location=location)


def swap_declined(ns: str) -> py_trees.composites.Sequence:
    """On no, tell the person where the other item is."""
    say = Act(
        "say where the other item is",
        with_offer(_say_free),
        ns,
        says=lambda c: f"{_occupied(c).person}, the {_occupied(c).offer} is free.",
    )
    children: list[py_trees.behaviour.Behaviour] = [
        go_to("go to the person", _person_cell, ns),
        say,
    ]
    return py_trees.composites.Sequence("swap declined", memory=True, children=children)


def swap_branch(ns: str) -> TaskBranch:
    """A person's preferred item is held by someone else: say so, then ask for a swap."""
    say = Act(
        "say it is occupied",
        lambda c: Say(
            person=_occupied(c).person,
            item=_occupied(c).item,
            topic=SayTopic.OCCUPIED,
            holder=_occupied(c).holder,
        ),
        ns,
        says=lambda c: (
            f"{_occupied(c).person}, {_occupied(c).holder} is playing with the {_occupied(c).item}."
        ),
    )
    ask = py_trees.composites.Selector("ask", memory=True, children=[swap_accepted(ns), swap_declined(ns)])
    return TaskBranch(
        "swap",
        ns,
        [
            FindTask("preferred item occupied?", "swap", occupied_tasks, ns),
            go_to("go to the person", _person_cell, ns, guarded=True),
            say,
            ask,
        ],
    )


def put_back_branch(ns: str, finder: Finder = put_back_unless_deceived) -> TaskBranch:
    """An item was moved while the person who left it was away: bring it back (``finder``:
    which items; the ``tidy`` policy puts back every one that was moved)."""
    return TaskBranch(
        "put back",
        ns,
        [
            FindTask("moved?" if finder is tidy_tasks else "moved while away?", "put back", finder, ns),
            go_to("go to the item", lambda c: c.cell_of_item(_put_back(c).item), ns, guarded=True),
            Act("pick it", lambda c: Pick(item=_put_back(c).item), ns),
            go_to("go to its place", lambda c: c.location_cell(_put_back(c).location), ns),
            Act("put it there", lambda c: Place(location=_put_back(c).location), ns),
        ],
    )


def _look(ctx: RobotContext) -> Look:
    assert isinstance(ctx.task, Look)
    return ctx.task


def seeing_cell(ctx: RobotContext) -> Step:
    """A walk to the nearest cell that sees the look's location (``SKIP``: the robot sees it)."""
    snap = ctx.snapshot
    me = ctx.cell_of(ctx.robot)
    if snap is None or me is None:
        return None
    model = snap.model
    here = model.cell_index.get(me)
    where = model.locations.index(_look(ctx).location)
    if here is not None and model.sees[here, where]:
        return Skip.SKIP
    seeing = np.flatnonzero(model.sees[:, where])
    if here is None or len(seeing) == 0:
        return None
    best = int(seeing[np.argmin(cell_distances(model)[here, seeing])])
    col, row = (int(v) for v in model.cells[best])
    return Navigate(cell=Cell(col, row))


def look_branch(ns: str) -> TaskBranch:
    """The robot cannot rule out other places for an item someone may need to be told of:
    go where it sees the likeliest one (what it sees there settles where the item is)."""
    return TaskBranch(
        "look",
        ns,
        [
            FindTask("worth looking?", "look", look_chosen, ns),
            Act("go and look", seeing_cell, ns, timeout=navigate_timeout, guarded=True),
        ],
    )


def _question(ctx: RobotContext) -> AskWhat:
    assert isinstance(ctx.task, AskWhat)
    return ctx.task


def ask_branch(ns: str) -> TaskBranch:
    """The robot cannot tell what a person is looking for, and what they would answer is worth
    more than the interruption: go to them and ask (their answer is evidence about what they
    want: :mod:`brain.model.answers`)."""
    ask = Act(
        "ask what they want",
        lambda c: Ask(person=_question(c).person),
        ns,
        says=lambda c: f"{_question(c).person}, what are you looking for?",
        timeout=answer_timeout,
    )
    return TaskBranch(
        "ask",
        ns,
        [
            FindTask("worth asking?", "ask", question_chosen, ns),
            go_to("go to the person", lambda c: c.cell_of(_question(c).person), ns, guarded=True),
            ask,
        ],
    )


POLICIES = ROBOT_POLICIES
"""The robot's policies: ``tom`` (the paper's tree, acting on the people's inferred minds),
``benefit`` (the same minds, each task chosen by its expected benefit, and asking or looking
where that is worth it),
two without theory of mind to measure it against: ``tidy`` (put every moved item back
where it was) and ``announce`` (tell everyone about every move), and ``oracle``: ``tom``'s tree
on the simulated people's true minds (an upper bound, not a robot one could build:
:mod:`brain.robot.oracle`)."""


def build_tree(namespace: str, policy: Policy = Policy.TOM) -> py_trees.behaviour.Behaviour:
    """The robot's tree for ``policy``; its behaviours use the context at ``<namespace>/context``
    (``tom`` and ``oracle`` share one tree: they differ in the minds it reads)."""
    if policy == Policy.TIDY:
        branches = [put_back_branch(namespace, tidy_tasks)]
    elif policy == Policy.ANNOUNCE:
        branches = [inform_branch(namespace, announce_tasks)]
    elif policy == Policy.BENEFIT:
        branches = [
            ask_branch(namespace),
            inform_branch(namespace, benefit_inform),
            swap_branch(namespace),
            put_back_branch(namespace, benefit_put_back),
            look_branch(namespace),
        ]
    else:
        branches = [inform_branch(namespace), swap_branch(namespace), put_back_branch(namespace)]
    return py_trees.composites.Selector("robot", memory=False, children=[*branches, GoHome(namespace)])
