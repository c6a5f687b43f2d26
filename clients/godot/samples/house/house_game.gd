extends Reference
# The house as the game behind an engine host (addons/toyroom/engine_host.gd): scenarios by
# name from a folder of `toyroom export-scenario` files, the scene described from a TileMap.

const Scenario = preload("res://samples/house/scenario.gd")
const House = preload("res://samples/house/house.gd")
const TileMapScene = preload("res://addons/toyroom/tilemap_scene.gd")
const TICK_SECONDS := 0.7  # one cell per tick, as the Python grid engine (by default)
const ENGINE := "toyroom Godot house 0.1 (sample, Godot %s)"

var folder := "."
var robot_override = null  # true: act, false: observe, null: as the scenario says
var map: TileMap  # the scenario's map, built from its scene and described from the tiles
var scenario
var world
var episode_ := 0
var seconds := TICK_SECONDS  # simulated seconds per tick (script durations are scaled to it)


func _init(scenarios_folder: String, the_map: TileMap, robot = null, tick_seconds_ := TICK_SECONDS) -> void:
	folder = scenarios_folder
	map = the_map
	robot_override = robot
	seconds = tick_seconds_


func load_scenario(name: String) -> String:
	# Load a scenario by name, by an export's path, or by a .toml path whose export lies in the
	# folder under its stem; "" or why not.
	var stem := name.get_file().get_basename() if name.ends_with(".toml") else name
	var path := name if name.ends_with(".json") else folder.plus_file(stem + ".json")
	if not File.new().file_exists(path):
		return "no scenario '%s' (no %s)" % [name, path]
	var next = Scenario.read(path)
	if next.error != "":
		return next.error
	var problems: Array = TileMapScene.build(map, next.scene)
	if not problems.empty():
		printerr("toyroom: the map of '%s' does not fit a TileMap: %s" % [name, PoolStringArray(problems).join("; ")])
	scenario = next
	var acts: bool = robot_override if robot_override != null else scenario.robot_acts
	world = House.new(scenario, episode_, seconds, acts)
	return ""


func tick_seconds() -> float:
	return seconds


func episode() -> int:
	return episode_


func engine_info(world_name: String, clock: String) -> Dictionary:
	var scene: Dictionary = TileMapScene.export_scene(map)
	var agents := []
	for agent in scenario.scene["agents"]:
		var copy: Dictionary = agent.duplicate(true)
		copy["acts"] = agent["kind"] != "robot" or world.acts
		agents.append(copy)
	scene["agents"] = agents
	scene["items"] = scenario.scene["items"]
	if scenario.scene.get("household") != null:
		scene["household"] = scenario.scene["household"]
	return {
		"type": "engine_info", "protocol": House.PROTOCOL, "engine": ENGINE % Engine.get_version_info()["string"],
		"world": world_name, "scenario": scenario.name, "capabilities": ["lockstep", "realtime", "robot"],
		"clock": clock, "tick_seconds": seconds, "episode": episode_, "scene": scene,
	}


func reset(name) -> String:
	episode_ += 1
	var why := load_scenario(name if name != null else scenario.name)
	if why != "":
		episode_ -= 1  # a failed reset starts no episode
	return why


func tick() -> Dictionary:
	world.step()
	return {"events": world.events, "statuses": world.executor.drain(), "state": world.state()}


func command(message: Dictionary) -> Array:
	world.executor.receive(message)
	return world.executor.drain()


func stop_robot(reason: String) -> Array:
	world.executor.stop_all(reason)
	return world.executor.drain()


func state() -> Dictionary:
	return world.state()
