extends Reference
# A scenario as `toyroom export-scenario` writes it (format toyroom-scenario/1): the protocol
# scene (regions with their cells, doors, locations, visibility, agents, items) and the
# items' places, the agents' homes, wishes, answers and scripts.

const Json = preload("res://addons/toyroom/json_writer.gd")
const FORMAT := "toyroom-scenario/1"

var name := ""
var robot_acts := false
var tick_seconds := 0.1  # of the scenario's own ticks (script `ticks` count in these)
var max_ticks := 3000
var settle_ticks := 1
var scene := {}
var items := []  # {id, at, absent}
var agents := []  # {id, kind, name, home: {col, row}, wants, answers, script}
var region_at := {}  # Vector2 cell -> region id
var walkable := {}  # Vector2 cell -> true
var locations := {}  # id -> location
var error := ""  # why the file could not be read ("" when it was)


static func read(path: String):
	var scenario = load("res://samples/house/scenario.gd").new()
	var file := File.new()
	if file.open(path, File.READ) != OK:
		scenario.error = "cannot read scenario %s" % path
		return scenario
	var got = Json.read(file.get_as_text())
	file.close()
	var data = got[0]
	if got[1] != "" or typeof(data) != TYPE_DICTIONARY or data.get("format") != FORMAT:
		scenario.error = "%s: not a %s export (toyroom export-scenario)" % [path, FORMAT]
		return scenario
	scenario.name = data["name"]
	scenario.robot_acts = data.get("robot") == "act"
	scenario.tick_seconds = float(data["tick_seconds"])
	scenario.max_ticks = int(data["max_ticks"])
	scenario.settle_ticks = int(data["settle_ticks"])
	scenario.scene = data["scene"]
	scenario.items = data["items"]
	scenario.agents = data["agents"]
	scenario.index()
	return scenario


func index() -> void:
	region_at = {}
	walkable = {}
	locations = {}
	for region in scene["regions"]:
		for c in region["cells"]:
			region_at[Vector2(c["col"], c["row"])] = region["id"]
			walkable[Vector2(c["col"], c["row"])] = true
	for door in scene["doors"]:
		walkable[Vector2(door["cell"]["col"], door["cell"]["row"])] = true
	for location in scene["locations"]:
		locations[location["id"]] = location


func scaled(ticks, engine_tick: float):
	# A duration in the scenario's ticks, in an engine's ticks of `engine_tick` s.
	if ticks == null:
		return null
	return int(max(1, ceil(ticks * tick_seconds / engine_tick)))
