extends Reference
# The robot's commands (protocol/README.md, `robot_command` and `command_status`): checks a
# command when it arrives (failed at once with a reason, or `accepted` and queued), runs one at
# a time in arrival order (`running` on the tick its work starts, then one of `succeeded`,
# `failed` with a reason, `cancelled`), does a `cancel` at once (the cancel `accepted`, its
# target `cancelled`, the cancel `succeeded`; an unknown target: `failed`), and stops
# everything when the brain falls silent (stop_all).
#
# The world it acts in is any object with these methods (the sample's house.gd has them):
#   tick() -> int; robot_id() -> String; robot_acts() -> bool
#   has_person(id) -> bool; has_item(id) -> bool; location(id) -> Dictionary or null
#   is_walkable(cell: Vector2) -> bool; cell_of(agent) -> Vector2; region_of(agent) -> String
#   holding(agent) -> item id or null
#   plan_path(agent, cell: Vector2) -> bool (false: unreachable); path_left(agent) -> int
#   clear_path(agent); move(agent)   (one cell along the path, with leave/enter events)
#   take(agent, item) -> String; drop(agent, location) -> String   ("" or why not, with events)
#   hand(giver, receiver)             (with the give event)
#   event(kind, actor, fields: Dictionary)
#   person_told(person, item, location); person_given(person); person_answers(person) -> bool
#   person_handed_over(person); person_wants(person) -> item id or null

const PROTOCOL := "1.7"
const KINDS := ["navigate", "pick", "place", "give", "say", "request", "ask", "cancel"]
const EARSHOT_CELLS := 2

var world
var statuses := []  # the command statuses made since the last drain(), in order
var queue := []
var running = null
var seen_ids := {}


func _init(the_world) -> void:
	world = the_world


func drain() -> Array:
	var out := statuses
	statuses = []
	return out


func idle() -> bool:
	return running == null and queue.empty()


func status(command: Dictionary, state: String, reason := "", answer = null):
	statuses.append({
		"type": "command_status", "protocol": PROTOCOL, "command": str(command.get("id", "")),
		"robot": str(command.get("robot", "")), "state": state, "tick": world.tick(),
		"reason": reason, "answer": answer,
	})


static func near(a: Vector2, b: Vector2) -> bool:
	# Next to: the same cell or one sharing an edge.
	return abs(a.x - b.x) + abs(a.y - b.y) <= 1


static func text_cell(cell: Vector2) -> String:
	return "(%d,%d)" % [int(cell.x), int(cell.y)]


func within_earshot(person: String) -> bool:
	# The protocol's earshot: the same region, or within 2 cells Manhattan, walls ignored.
	var me = world.robot_id()
	var a: Vector2 = world.cell_of(me)
	var b: Vector2 = world.cell_of(person)
	return world.region_of(me) == world.region_of(person) or abs(a.x - b.x) + abs(a.y - b.y) <= EARSHOT_CELLS


# ----- arrival -----------------------------------------------------------------------------


func receive(command: Dictionary):
	# A command arrived: fail it at once with a reason, or accept (queue) it; a cancel is done.
	var action = command.get("action")
	var robot = command.get("robot")
	if typeof(command.get("id")) != TYPE_STRING or typeof(robot) != TYPE_STRING or typeof(action) != TYPE_DICTIONARY:
		return status(command, "failed", "bad command: expected a string 'id', a string 'robot' and an 'action' object")
	if robot != world.robot_id():
		return status(command, "failed", "unknown robot '%s'" % robot)
	if not world.robot_acts():
		return status(command, "failed", "robot '%s' only observes" % robot)
	if seen_ids.has(command["id"]):
		return status(command, "failed", "duplicate command id '%s'" % command["id"])
	seen_ids[command["id"]] = true
	var kind = action.get("kind")
	if kind == "cancel":
		return _cancel(command, action)
	var problem := check(kind, action)
	if problem != "":
		return status(command, "failed", problem)
	status(command, "accepted")
	queue.append(command)


func check(kind, action: Dictionary) -> String:
	# Why the action can never be done (an unknown kind, id or cell), or "".
	if not kind in KINDS:
		return "unknown command kind '%s' (this engine does %s)" % [kind, PoolStringArray(KINDS).join(", ")]
	match kind:
		"navigate":
			var cell = action.get("cell")
			if typeof(cell) != TYPE_DICTIONARY or not _is_int(cell.get("col")) or not _is_int(cell.get("row")):
				return "bad navigate: expected a 'cell' {col, row} of integers"
			var at := Vector2(cell["col"], cell["row"])
			if not world.is_walkable(at):
				return "not walkable: " + text_cell(at)
		"pick":
			if not world.has_item(str(action.get("item"))):
				return "unknown id '%s': no such item" % action.get("item")
		"place":
			if world.location(str(action.get("location"))) == null:
				return "unknown id '%s': no such location" % action.get("location")
		"give", "say", "request", "ask":
			if not world.has_person(str(action.get("person"))):
				return "unknown id '%s': no such person" % action.get("person")
			if kind == "request" and not world.has_item(str(action.get("item"))):
				return "unknown id '%s': no such item" % action.get("item")
			if kind == "say" and not action.get("topic") in ["location", "occupied"]:
				return "bad say: topic must be 'location' or 'occupied', got '%s'" % action.get("topic")
	return ""


static func _is_int(value) -> bool:
	return typeof(value) == TYPE_INT or (typeof(value) == TYPE_REAL and value == floor(value))


func _cancel(command: Dictionary, action: Dictionary):
	var target = action.get("command")
	var victim = null
	if running != null and running["id"] == target:
		victim = running
	else:
		for queued in queue:
			if queued["id"] == target:
				victim = queued
	if victim == null:
		return status(command, "failed", "no queued or running command '%s'" % target)
	if victim == running:
		running = null
		world.clear_path(world.robot_id())
	else:
		queue.erase(victim)
	status(command, "accepted")
	status(victim, "cancelled", "cancelled by '%s'" % command["id"])
	status(command, "succeeded")


func stop_all(reason: String) -> void:
	# Fail the running command and every queued one with `reason` (the brain fell silent).
	if running != null:
		world.clear_path(world.robot_id())
		finish("failed", reason)
	for queued in queue:
		status(queued, "failed", reason)
	queue = []


func reset() -> void:
	# A reset ends every command without a final status; ids may be used again.
	queue = []
	running = null
	seen_ids = {}
	statuses = []


# ----- one tick ----------------------------------------------------------------------------


func update():
	# The robot's tick: start the next command (its work begins this tick) and work on it.
	var me = world.robot_id()
	if me == null or me == "":
		return
	if running == null:
		if queue.empty():
			return
		running = queue.pop_front()
		status(running, "running")
		var action: Dictionary = running["action"]
		if action["kind"] == "navigate":
			var goal := Vector2(action["cell"]["col"], action["cell"]["row"])
			if not world.plan_path(me, goal):
				return finish("failed", "unreachable: no path to " + text_cell(goal))
	var action: Dictionary = running["action"]
	var reason := ""
	match action["kind"]:
		"navigate":
			world.move(me)
			if world.path_left(me) == 0:
				finish("succeeded")
			return
		"pick":
			reason = world.take(me, action["item"])
		"place":
			reason = world.drop(me, action["location"])
		"give":
			reason = _give(me, action["person"])
		"say":
			reason = _say(me, action)
		"ask":
			return _ask(me, action)
		"request":
			var person: String = action["person"]
			if world.holding(person) != action["item"]:
				reason = "%s does not hold '%s'" % [person, action["item"]]
			elif not near(world.cell_of(me), world.cell_of(person)):
				reason = "out of reach: " + person
			else:
				var answer: bool = world.person_answers(person)
				world.event("request", me, {"item": action["item"], "target": person, "offer": action.get("offer")})
				world.event("reply", person, {"item": action["item"], "target": me, "answer": answer})
				if answer:
					world.hand(person, me)
					world.person_handed_over(person)
				return finish("succeeded", "", answer)
	finish("failed" if reason != "" else "succeeded", reason)


func _give(me: String, person: String) -> String:
	if world.holding(me) == null:
		return "hands empty"
	if not near(world.cell_of(me), world.cell_of(person)):
		return "out of reach: " + person
	if world.holding(person) != null:
		return "%s's hands are full" % person
	world.hand(me, person)
	world.person_given(person)
	return ""


func _say(me: String, action: Dictionary) -> String:
	# Heard within earshot: one `say` event per item told, all on this tick.
	var person: String = action["person"]
	if not within_earshot(person):
		return "out of earshot: " + person
	if action["topic"] != "location":
		world.event("say", me, {"item": action.get("item"), "target": person, "detail": "occupied by %s" % action.get("holder")})
		return ""
	var told := [[action.get("item"), action.get("location")]]
	var also = action.get("also")
	if typeof(also) == TYPE_ARRAY:
		for more in also:
			if typeof(more) == TYPE_DICTIONARY:
				told.append([more.get("item"), more.get("location")])
	for pair in told:
		world.event("say", me, {"item": pair[0], "location": pair[1], "target": person})
		world.person_told(person, pair[0], pair[1])
	return ""


func _ask(me: String, action: Dictionary):
	# The person says truthfully what they want (an `answer` event; an open question when
	# `item` is null).
	var person: String = action["person"]
	if not within_earshot(person):
		return finish("failed", "out of earshot: " + person)
	var item = action.get("item")
	var wanted = world.person_wants(person)
	var said = item if item != null else wanted
	var wants: bool = (item == wanted) if item != null else (wanted != null)
	world.event("ask", me, {"item": item, "target": person})
	world.event("answer", person, {"item": said, "target": me, "answer": wants})
	finish("succeeded", "", wants)


func finish(state: String, reason := "", answer = null):
	status(running, state, reason, answer)
	running = null
