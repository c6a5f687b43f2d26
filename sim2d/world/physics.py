"""The pymunk world: static wall segments, agents as dynamic circles under velocity
control, items as small bodies pinned to their carrier while carried.

Velocity control happens inside pymunk's step, in each agent body's ``velocity_func``:
the commanded velocity replaces the integrated one *before* contacts are solved, so walls,
being hard contacts, always win (a body driven into a wall stops at it instead of tunnelling
through), and the controller sees the position already integrated this substep, so a body
told to cover exactly the remaining distance lands on its target.

The hot calls (each agent's velocity callback every substep, the substeps after the first,
reading a body's position or velocity) go straight to pymunk's chipmunk binding (``pymunk.cp``, the
pinned pymunk's ``Body._body`` and ``Space._space`` handles): the same C calls that pymunk's
properties and ``Space.step`` make, without their Python around them (a fifth of the tick;
``tests/sim2d/world/test_physics.py`` checks the stream against pymunk's own calls to the bit).

Agents collide with walls only (not with each other, so two people never deadlock in a
one-cell door); items collide with nothing. Time advances in fixed steps of
``dt / substeps`` seconds, so the same inputs always give the same trajectory.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import pymunk

from .walls import Segment

WALL_CATEGORY = 0b001
AGENT_CATEGORY = 0b010
ITEM_CATEGORY = 0b100
WALL_RADIUS = 0.05
"""Half the thickness of a wall segment, in metres."""
Controller = Callable[[tuple[float, float], float], tuple[float, float]]
"""``controller(position m, substep s) -> commanded velocity m/s``, called every substep."""


class Physics:
    """A fixed-step pymunk space.

    Args:
        walls: wall segments in metres.
        dt: seconds per tick.
        substeps: physics steps per tick.
    """

    def __init__(self, walls: list[Segment], dt: float, substeps: int = 5) -> None:
        self.dt = dt
        self.substeps = substeps
        self.space = pymunk.Space()
        self.space.iterations = 20
        self.space.damping = 1.0
        self.space.collision_slop = 0.01  # metres of overlap allowed at a contact
        self.bodies: dict[str, pymunk.Body] = {}
        self._pins: dict[str, pymunk.Constraint] = {}
        self._controlled: dict[str, Callable[[pymunk.Body, object, float, float], None]] = {}
        self._still: set[str] = set()
        static = self.space.static_body
        wall_filter = pymunk.ShapeFilter(categories=WALL_CATEGORY, mask=AGENT_CATEGORY)
        for a, b in walls:
            shape = pymunk.Segment(static, a, b, WALL_RADIUS)
            shape.filter = wall_filter
            shape.friction = 0.0
            shape.elasticity = 0.0
            self.space.add(shape)

    def add_agent(
        self, agent_id: str, position: tuple[float, float], radius: float, controller: Controller
    ) -> pymunk.Body:
        """A dynamic circle of ``radius`` metres, moved by ``controller``, that only walls stop."""
        body = pymunk.Body(mass=60.0, moment=math.inf)
        body.position = position
        shape = pymunk.Circle(body, radius)
        shape.filter = pymunk.ShapeFilter(categories=AGENT_CATEGORY, mask=WALL_CATEGORY)
        shape.friction = 0.0
        shape.elasticity = 0.0

        handle, get_position = body._body, pymunk.cp.cpBodyGetPosition
        set_velocity = pymunk.cp.cpBodySetVelocity

        def velocity_func(body: pymunk.Body, gravity: object, damping: float, dt: float) -> None:
            p = get_position(handle)  # body.position and body.velocity = ..., without their Python
            set_velocity(handle, controller((p.x, p.y), dt))

        body.velocity_func = velocity_func
        self._controlled[agent_id] = velocity_func
        self.space.add(body, shape)
        self.bodies[agent_id] = body
        return body

    def hold_still(self, agent_id: str, still: bool) -> None:
        """Whether an agent's controller sits out the next :meth:`step`: only for an agent at
        rest (zero velocity, no contact, nothing pinned to it) whose controller would answer
        zero every substep, so that the trajectory is the same to the bit; pymunk's own
        velocity update (in C) then keeps it at rest, without a Python call per substep."""
        if still == (agent_id in self._still):
            return
        body = self.bodies[agent_id]
        if still:
            body.velocity_func = pymunk.Body.update_velocity
            self._still.add(agent_id)
        else:
            body.velocity_func = self._controlled[agent_id]
            self._still.discard(agent_id)

    def at_rest(self, body_id: str) -> bool:
        """Whether a body's velocity is exactly zero."""
        v = pymunk.cp.cpBodyGetVelocity(self.bodies[body_id]._body)
        return v.x == 0.0 and v.y == 0.0

    def add_item(self, item_id: str, position: tuple[float, float], radius: float = 0.12) -> pymunk.Body:
        """A small body that collides with nothing."""
        body = pymunk.Body(mass=0.5, moment=pymunk.moment_for_circle(0.5, 0, radius))
        body.position = position
        shape = pymunk.Circle(body, radius)
        shape.filter = pymunk.ShapeFilter(categories=ITEM_CATEGORY, mask=0)
        self.space.add(body, shape)
        self.bodies[item_id] = body
        return body

    def attach(self, item_id: str, carrier_id: str) -> None:
        """Pin an item to its carrier (it moves with it) until :meth:`detach`."""
        self.detach_pin(item_id)
        item, carrier = self.bodies[item_id], self.bodies[carrier_id]
        item.position = carrier.position
        item.velocity = carrier.velocity
        pin = pymunk.PivotJoint(carrier, item, (0, 0), (0, 0))
        pin.collide_bodies = False
        self.space.add(pin)
        self._pins[item_id] = pin

    def detach_pin(self, item_id: str) -> None:
        pin = self._pins.pop(item_id, None)
        if pin is not None:
            self.space.remove(pin)

    def put_down(self, item_id: str, position: tuple[float, float]) -> None:
        """Unpin an item and set it down at rest at ``position`` (m)."""
        self.detach_pin(item_id)
        body = self.bodies[item_id]
        body.position = position
        body.velocity = (0.0, 0.0)
        body.angular_velocity = 0.0

    def step(self) -> None:
        """Advance one tick (``substeps`` fixed steps): the first through ``Space.step``,
        which also does pymunk's bookkeeping of bodies added or removed since the last
        tick; the others straight through chipmunk (nothing is added or removed during a
        tick: no callback here changes the space)."""
        sub_dt = self.dt / self.substeps
        self.space.step(sub_dt)
        space, step = self.space._space, pymunk.cp.cpSpaceStep
        for _ in range(self.substeps - 1):
            step(space, sub_dt)

    def position(self, body_id: str) -> tuple[float, float]:
        """A body's position (m)."""
        p = pymunk.cp.cpBodyGetPosition(self.bodies[body_id]._body)
        return (p.x, p.y)

    def velocity(self, body_id: str) -> tuple[float, float]:
        """A body's velocity (m/s)."""
        v = pymunk.cp.cpBodyGetVelocity(self.bodies[body_id]._body)
        return (v.x, v.y)
