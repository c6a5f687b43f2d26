extends Reference
# The house: one episode of a scenario on the grid. People and the robot move one cell per
# tick along shortest paths and act at once; every tick makes the protocol's events, the
# robot's command statuses (the add-on's robot executor) and a state, as dictionaries ready
# for the JSON writer. A GDScript port of the Python grid engine's world
# (examples/grid_engine/grid_world.py), tick for tick.

const PROTOCOL := "1.7"
const Person = preload("res://samples/house/person.gd")
const RobotExecutor = preload("res://addons/toyroom/robot_executor.gd")
const NEIGHBOURS := [Vector2(1, 0), Vector2(-1, 0), Vector2(0, 1), Vector2(0, -1)]

var scenario
var episode := 0
var tick_seconds := 0.7
var acts := true
var tick_count := 0
var events := []
var labels := {}  # "person:label" -> true
var cells := {}  # agent -> Vector2
var regions := {}  # agent -> region id
var paths := {}  # agent -> Array of Vector2
var holding_ := {}  # agent -> item id or null
var playing := {}  # agent -> bool
var moved := {}
var items := {}  # item -> {location, holder}
var people := {}  # id -> Person
var robot := ""
var executor
var settle := 1
var max_ticks := 1
var quiet := 0
var done := false


func _init(the_scenario, the_episode: int, seconds: float, robot_acts_: bool) -> void:
	scenario = the_scenario
	episode = the_episode
	tick_seconds = seconds
	acts = robot_acts_
	for agent in scenario.agents:
		var home := Vector2(agent["home"]["col"], agent["home"]["row"])
		cells[agent["id"]] = home
		regions[agent["id"]] = scenario.region_at.get(home, "")
		paths[agent["id"]] = []
		holding_[agent["id"]] = null
		playing[agent["id"]] = false
	for item in scenario.items:
		if item.get("absent", false):
			continue  # not in the scene: in no state
		if cells.has(item["at"]):
			items[item["id"]] = {"location": null, "holder": item["at"]}
			holding_[item["at"]] = item["id"]
		else:
			items[item["id"]] = {"location": item["at"], "holder": null}
	for agent in scenario.agents:
		if agent["kind"] == "person":
			people[agent["id"]] = Person.new(agent, scenario, seconds)
		elif agent["kind"] == "robot" and robot == "":
			robot = agent["id"]
	executor = RobotExecutor.new(self)
	var s = scenario.scaled(scenario.settle_ticks, seconds)
	settle = s if s != null and s > 0 else 1
	var m = scenario.scaled(scenario.max_ticks, seconds)
	max_ticks = m if m != null and m > 0 else 1


# ----- what the robot executor needs ----------------------------------------------------------


func tick() -> int:
	return tick_count


func robot_id() -> String:
	return robot


func robot_acts() -> bool:
	return acts


func has_person(id: String) -> bool:
	return people.has(id)


func has_item(id: String) -> bool:
	return items.has(id)


func location(id):
	return scenario.locations.get(id)


func is_walkable(cell: Vector2) -> bool:
	return scenario.walkable.has(cell)


func cell_of(agent: String) -> Vector2:
	return cells[agent]


func region_of(agent: String) -> String:
	return regions[agent]


func holding(agent: String):
	return holding_[agent]


func plan_path(agent: String, goal: Vector2) -> bool:
	var path = bfs(cells[agent], {goal: true})
	if path == null:
		return false
	paths[agent] = path
	return true


func path_left(agent: String) -> int:
	return paths[agent].size()


func clear_path(agent: String) -> void:
	paths[agent] = []


func person_told(person: String, item, where) -> void:
	# Told where the item they want rests: they go and fetch it, then play.
	var who = people[person]
	if item == who.wants and holding_[person] == null:
		who.replace([{"do": "goto", "location": where}, {"do": "take", "item": item}, {"do": "goto"}, {"do": "play"}])


func person_given(person: String) -> void:
	people[person].replace([{"do": "goto"}, {"do": "play"}])


func person_answers(person: String) -> bool:
	return people[person].answers


func person_handed_over(person: String) -> void:
	people[person].replace([{"do": "wait"}])


func person_wants(person: String):
	return people[person].wants


# ----- messages ------------------------------------------------------------------------------


func time() -> float:
	return stepify(tick_count * tick_seconds, 1e-9)


func event(kind: String, actor: String, fields := {}) -> void:
	var message := {
		"type": "event", "protocol": PROTOCOL, "episode": episode, "tick": tick_count, "time": time(),
		"kind": kind, "actor": actor,
	}
	for key in fields:
		message[key] = fields[key]
	events.append(message)


static func cell_dict(cell: Vector2) -> Dictionary:
	return {"col": int(cell.x), "row": int(cell.y)}


func state() -> Dictionary:
	var size: float = scenario.scene["cell_size"]
	var agents := []
	for agent in cells:
		var cell: Vector2 = cells[agent]
		agents.append({
			"id": agent, "pose": {"x": (cell.x + 0.5) * size, "y": (cell.y + 0.5) * size, "theta": 0.0},
			"velocity": {"x": 0.0, "y": 0.0}, "cell": cell_dict(cell), "region": regions[agent],
			"holding": holding_[agent],
			"activity": "playing" if playing[agent] else "moving" if moved.has(agent) else "idle",
		})
	var out_items := []
	for item in items:
		var where: Dictionary = items[item]
		var cell: Vector2
		var region: String
		if where["holder"] != null:
			cell = cells[where["holder"]]
			region = regions[where["holder"]]
		else:
			var loc: Dictionary = scenario.locations[where["location"]]
			cell = Vector2(loc["cell"]["col"], loc["cell"]["row"])
			region = loc["region"]
		out_items.append({
			"id": item, "pose": {"x": (cell.x + 0.5) * size, "y": (cell.y + 0.5) * size, "theta": 0.0},
			"cell": cell_dict(cell), "region": region, "location": where["location"], "held_by": where["holder"],
		})
	return {
		"type": "state", "protocol": PROTOCOL, "episode": episode, "tick": tick_count, "time": time(),
		"agents": agents, "items": out_items, "done": done,
	}


# ----- shared actions ------------------------------------------------------------------------


func bfs(start: Vector2, goals: Dictionary):
	# Cells from `start` (excluded) to the nearest goal (included); null if unreachable.
	if goals.has(start):
		return []
	var came := {}
	var seen := {start: true}
	var queue := [start]
	var head := 0
	while head < queue.size():
		var cell: Vector2 = queue[head]
		head += 1
		for step in NEIGHBOURS:
			var next: Vector2 = cell + step
			if scenario.walkable.has(next) and not seen.has(next):
				seen[next] = true
				came[next] = cell
				if goals.has(next):
					var path := [next]
					while came.has(path[-1]) and came[path[-1]] != start:
						path.append(came[path[-1]])
					path.invert()
					return path
				queue.append(next)
	return null


func move(agent: String) -> void:
	# One cell along the agent's path, with `leave` and `enter` between regions.
	if paths[agent].empty():
		return
	var cell: Vector2 = paths[agent].pop_front()
	cells[agent] = cell
	moved[agent] = true
	var region = scenario.region_at.get(cell)
	if region != null and region != regions[agent]:
		event("leave", agent, {"location": regions[agent]})
		event("enter", agent, {"location": region})
		regions[agent] = region


func take(agent: String, item: String) -> String:
	if not items.has(item):
		return "unknown id '%s': no such item" % item
	var where: Dictionary = items[item]
	if holding_[agent] != null:
		return "hands full: %s holds '%s'" % [agent, holding_[agent]]
	if where["holder"] != null:
		return "item held by %s" % where["holder"]
	var loc = location(where["location"]) if where["location"] != null else null
	if loc == null or not RobotExecutor.near(cells[agent], Vector2(loc["cell"]["col"], loc["cell"]["row"])):
		return "item not there: '%s' is at %s" % [item, where["location"]]
	event("take", agent, {"item": item, "location": where["location"]})
	where["location"] = null
	where["holder"] = agent
	holding_[agent] = item
	return ""


func drop(agent: String, location_id: String) -> String:
	var item = holding_[agent]
	var loc = location(location_id)
	if item == null:
		return "hands empty"
	if loc == null or not RobotExecutor.near(cells[agent], Vector2(loc["cell"]["col"], loc["cell"]["row"])):
		return "out of reach: location %s" % location_id
	var here := 0
	for other in items:
		if items[other]["location"] == location_id:
			here += 1
	if loc.get("capacity") != null and here >= loc["capacity"]:
		return "location full: %s holds at most %d" % [location_id, loc["capacity"]]
	items[item] = {"location": location_id, "holder": null}
	holding_[agent] = null
	playing[agent] = false
	event("drop", agent, {"item": item, "location": location_id})
	return ""


func hand(giver: String, receiver: String) -> void:
	var item = holding_[giver]
	holding_[giver] = null
	playing[giver] = false
	holding_[receiver] = item
	items[item]["holder"] = receiver
	event("give", giver, {"item": item, "target": receiver})


func spot_at(cell: Vector2):
	for loc in scenario.scene["locations"]:
		if Vector2(loc["cell"]["col"], loc["cell"]["row"]) == cell:
			return loc
	return null


# ----- the tick ------------------------------------------------------------------------------


func step() -> void:
	tick_count += 1
	events = []
	moved = {}
	for id in people:
		update_person(people[id])
	executor.update()
	var all_finished := true
	for id in people:
		if not people[id].finished():
			all_finished = false
	quiet = quiet + 1 if all_finished and executor.idle() else 0
	if quiet >= settle or tick_count >= max_ticks:
		done = true


func complete(person, label) -> void:
	if label != null and str(label) != "":
		labels[person.id + ":" + str(label)] = true
		event("waypoint", person.id, {"label": label, "location": regions[person.id]})
	person.index += 1
	person.started = false


func update_person(person) -> void:
	# One tick of a scripted person: a move or one action.
	var agent: String = person.id
	while person.index < person.plan.size():
		var step: Dictionary = person.plan[person.index]
		var action: String = step["do"]
		if action == "enter" or action == "goto":
			if not person.started:
				person.started = true
				var goals := {}
				if action == "enter":
					for cell in scenario.region_at:
						if scenario.region_at[cell] == step["region"]:
							goals[cell] = true
				elif step.has("location"):
					var loc: Dictionary = scenario.locations[step["location"]]
					goals[Vector2(loc["cell"]["col"], loc["cell"]["row"])] = true
				elif step.has("cell"):
					goals[Vector2(step["cell"][0], step["cell"][1])] = true
				else:
					for loc in scenario.scene["locations"]:
						if loc.get("play", false):
							goals[Vector2(loc["cell"]["col"], loc["cell"]["row"])] = true
				var path = bfs(cells[agent], goals)
				paths[agent] = path if path != null else []
			if not paths[agent].empty():
				move(agent)
				if not paths[agent].empty():
					return
				complete(person, step.get("label"))
				return
			complete(person, step.get("label"))
			continue
		if action == "take" or action == "drop":
			var here = spot_at(cells[agent])
			var reason := ""
			if action == "take":
				reason = take(agent, step["item"])
			else:
				reason = "no spot here" if here == null else drop(agent, here["id"])
			complete(person, step.get("label") if reason == "" else null)
			return
		if not person.started:  # play, use or wait begins
			person.started = true
			person.left = step.get("ticks", 0) if step.get("ticks") != null else 0
			if action == "play":
				if holding_[agent] == null:
					complete(person, null)
					continue
				playing[agent] = true
				var spot = spot_at(cells[agent])
				event("play", agent, {"item": holding_[agent], "location": spot["id"] if spot != null else null})
			if action == "use":
				var where = items.get(step["item"], {}).get("location")
				var loc = location(where) if where != null else null
				if loc == null or not loc.get("use", false) or not RobotExecutor.near(cells[agent], Vector2(loc["cell"]["col"], loc["cell"]["row"])):
					complete(person, null)
					continue
				playing[agent] = true
				event("use", agent, {"item": step["item"], "location": where})
			if step.get("label") != null and str(step.get("label")) != "":
				labels[agent + ":" + str(step["label"])] = true
				event("waypoint", agent, {"label": step["label"], "location": regions[agent]})
			return
		if action == "play" and not playing[agent]:
			complete(person, null)
			continue
		if step.has("ticks"):
			person.left -= 1
			if person.left > 0:
				return
		elif step.has("until"):
			if not labels.has(step["until"]):
				return
		else:
			return
		if action == "play" or action == "use":
			playing[agent] = false
			event("stop", agent, {"item": holding_[agent] if action == "play" else step["item"]})
		person.index += 1
		person.started = false
