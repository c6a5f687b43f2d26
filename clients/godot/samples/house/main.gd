extends Node2D
# The sample: the paper's house (Fig. 5, `paper-robot`, and every other bundled scenario) as
# the engine of the world a `toyroom gateway` carries. Run headless:
#
#   godot3-server --path clients/godot -- --gateway ws://127.0.0.1:7448 --scenarios DIR \
#       [--scenario paper-robot] [--robot act|observe] [--realtime RATE] [--tick-seconds S]
#       [--token TEXT] [--name NAME] [--give-up SECONDS]
#
# DIR holds `toyroom export-scenario` files (NAME.json). Without --realtime the engine runs in
# lock-step; with it, a tick every S / RATE seconds of wall time. A tick is S simulated seconds
# (default 0.7: one cell per tick, as the Python grid engine). `-- --check-tilemap DIR` builds a TileMap from every export in DIR, describes it
# back and compares (exit 0: all the same). Exits 1 when no gateway answers for --give-up s.

const HouseGame = preload("res://samples/house/house_game.gd")
const LockstepHost = preload("res://addons/toyroom/lockstep_host.gd")
const RealtimeHost = preload("res://addons/toyroom/realtime_host.gd")
const TileMapScene = preload("res://addons/toyroom/tilemap_scene.gd")
const Scenario = preload("res://samples/house/scenario.gd")

var options := {
	"gateway": "ws://127.0.0.1:7448", "scenarios": ".", "scenario": "paper-robot", "robot": "",
	"realtime": "", "tick-seconds": "0.7", "token": "", "name": "godot", "give-up": "10", "log-level": "", "check-tilemap": "",
}
var link
var host
var _down_since := -1


func _ready() -> void:
	var problem := parse(OS.get_cmdline_args())
	if problem != "":
		printerr("godot house: " + problem)
		get_tree().quit(2)
		return
	if options["check-tilemap"] != "":
		get_tree().quit(check_tilemap(options["check-tilemap"]))
		return
	var robot = null if options["robot"] == "" else options["robot"] == "act"
	var game = HouseGame.new(options["scenarios"], $Map, robot, float(options["tick-seconds"]))
	var why: String = game.load_scenario(options["scenario"])
	if why != "":
		printerr("godot house: " + why)
		get_tree().quit(2)
		return
	if options["realtime"] != "":
		host = RealtimeHost.new()
		host.rate = float(options["realtime"])
	else:
		host = LockstepHost.new()
	host.name = "Host"
	add_child(host)
	link = get_node("/root/Toyroom")
	link.connect("welcomed", self, "_on_welcomed")
	link.connect("lost", self, "_on_lost")
	host.start(link, game)
	link.open(options["gateway"], "engine", options["name"], null if options["token"] == "" else options["token"])
	_down_since = OS.get_ticks_msec()


func parse(args: Array) -> String:
	# The options after `--`; "" or what is wrong.
	var at := args.find("--")
	var mine := args.slice(at + 1, args.size() - 1) if at >= 0 else []
	var i := 0
	while i < mine.size():
		var option: String = mine[i]
		if option == "--lockstep":
			i += 1
			continue
		if not option.begins_with("--") or not options.has(option.substr(2, option.length())):
			return "unknown option %s (options: --%s, --lockstep)" % [option, PoolStringArray(options.keys()).join(", --")]
		if i + 1 >= mine.size():
			return option + " needs a value"
		options[option.substr(2, option.length())] = mine[i + 1]
		i += 2
	if options["robot"] != "" and not options["robot"] in ["act", "observe"]:
		return "--robot takes act or observe, got '%s'" % options["robot"]
	if options["realtime"] != "" and not (options["realtime"].is_valid_float() and float(options["realtime"]) > 0):
		return "--realtime takes a rate above 0 (1: wall-clock speed), got '%s'" % options["realtime"]
	if not (options["tick-seconds"].is_valid_float() and float(options["tick-seconds"]) > 0):
		return "--tick-seconds takes seconds above 0, got '%s'" % options["tick-seconds"]
	if not options["give-up"].is_valid_float():
		return "--give-up takes seconds, got '%s'" % options["give-up"]
	return ""


func _on_welcomed(welcome: Dictionary) -> void:
	_down_since = -1
	print("godot house: scenario '%s' on world '%s'" % [host.game.scenario.name, welcome.get("world")])


func _on_lost(_reason: String) -> void:
	_down_since = OS.get_ticks_msec()


func _process(_delta: float) -> void:
	if _down_since >= 0 and OS.get_ticks_msec() - _down_since > float(options["give-up"]) * 1000.0:
		printerr("godot house: no gateway at %s for %s s: giving up" % [options["gateway"], options["give-up"]])
		get_tree().quit(1)
		_down_since = -1


func check_tilemap(folder: String) -> int:
	# Every export in `folder`: its scene into a TileMap and back; 0 when all come back the same.
	var dir := Directory.new()
	if dir.open(folder) != OK:
		printerr("godot house: cannot open " + folder)
		return 2
	var names := []
	dir.list_dir_begin(true, true)
	var name := dir.get_next()
	while name != "":
		if name.ends_with(".json"):
			names.append(name)
		name = dir.get_next()
	names.sort()
	var failed := 0
	for file in names:
		var scenario = Scenario.read(folder.plus_file(file))
		if scenario.error != "":
			printerr(scenario.error)
			failed += 1
			continue
		var map := TileMap.new()
		var problems: Array = TileMapScene.build(map, scenario.scene)
		var back: Dictionary = TileMapScene.export_scene(map)
		var diff: String = TileMapScene.same_map(scenario.scene, back)
		map.free()
		if not problems.empty() or diff != "":
			failed += 1
			print("tilemap %s: DIFFERS: %s" % [scenario.name, PoolStringArray(problems).join("; ") + diff])
		else:
			print("tilemap %s: the same (%d regions, %d doors, %d locations)" % [
				scenario.name, scenario.scene["regions"].size(), scenario.scene["doors"].size(), scenario.scene["locations"].size()])
	print("tilemap: %d of %d scenes the same" % [names.size() - failed, names.size()])
	return 0 if failed == 0 and not names.empty() else 1
