"""A task episode's first jobs (:class:`~sim2d.scenario.jobs.Jobs`) as an autonomous person
carries them out: standing where they are first (``wait``), then moving an item (``move``,
after ``move_after`` ticks), then the errand outside (``errand``, after ``errand_after``
ticks); each once, in that order. Their steps are marked ``errand``: carried through, so no
replanning, wandering or news stops the job."""

from __future__ import annotations

from ..scenario.jobs import Jobs
from ..world.world import World
from .pursuit import Primitive


class FirstJobs:
    """The first jobs a person has yet to plan."""

    def __init__(self, jobs: Jobs) -> None:
        self.wait = jobs.wait
        self.moves = jobs.moves
        self.move_after = jobs.move_after
        self.errand = jobs.errand
        self.errand_after = jobs.errand_after

    def next_steps(self, world: World, person: str) -> list[Primitive]:
        """The plan steps of ``person``'s next first job, which is then done with; empty when
        none is left to plan (a move of an item already held or moved, or an errand on a map
        without an outside, is dropped)."""
        if self.wait > 0:
            steps = [Primitive("wait", ticks=self.wait, errand=True)]
            self.wait = 0
            return steps
        if self.moves is not None:
            item, target = self.moves
            self.moves = None
            source = world.item_location(item)
            if source in world.locations and world.items[item].holder is None and source != target:
                src, dst = world.locations[source], world.locations[target]
                after = self.move_after
                return [
                    *([Primitive("wait", ticks=after, errand=True)] if after > 0 else []),
                    Primitive("goto", cell=(src.cell.col, src.cell.row), errand=True),
                    Primitive("take", item=item, errand=True),
                    Primitive("goto", cell=(dst.cell.col, dst.cell.row), errand=True),
                    Primitive("drop", location=target, errand=True),
                ]
        if self.errand > 0:
            ticks, self.errand = self.errand, 0
            outside = [c for c, r in world.region_of.items() if r in world.map.outside_regions]
            if outside:
                cell = world.agents[person].cell
                nearest = min(outside, key=lambda c: abs(c[0] - cell[0]) + abs(c[1] - cell[1]))
                after = self.errand_after
                return [
                    *([Primitive("wait", ticks=after, errand=True)] if after > 0 else []),
                    Primitive("goto", cell=nearest, errand=True),
                    Primitive("wait", ticks=ticks, errand=True),
                ]
        return []
