extends Node
# What both clocks share: the handshake on `engine/info`, the requests on `engine/control`
# (reset, pause, resume; `step` is the clock's own), robot commands and heartbeats, and
# publishing a tick (its events, then its command statuses, then its state).
#
# `game` is your world behind a small interface (the sample's house_game.gd has it):
#   engine_info(world: String, clock: String) -> Dictionary   (an engine_info message)
#   reset(scenario) -> String        ("" or why not: the scenario is unknown; null: the current)
#   tick() -> Dictionary             ({events, statuses, state}: one tick run)
#   command(command: Dictionary) -> Array   (the statuses it gets on arrival)
#   stop_robot(reason: String) -> Array     (the statuses of the commands it stopped)
#   state() -> Dictionary; episode() -> int

const PROTOCOL := "1.7"

var link  # the gateway link (the autoload Toyroom)
var game
var clock := "lockstep"
var paused := false
var world_name := ""


func start(gateway_link, the_game) -> void:
	link = gateway_link
	game = the_game
	link.serve("engine/info", self, "_on_info")
	link.serve("engine/control", self, "_on_control")
	link.subscribe("robot/*/command", self, "_on_command")
	link.subscribe("robot/*/heartbeat", self, "_on_heartbeat")
	link.connect("welcomed", self, "_on_welcomed")
	link.connect("lost", self, "_on_lost")


static func error(code: String, message: String) -> Dictionary:
	return {"type": "error", "protocol": PROTOCOL, "code": code, "message": message}


static func major(version) -> String:
	return str(version).split(".")[0]


func _on_welcomed(welcome: Dictionary) -> void:
	world_name = str(welcome.get("world", ""))
	print("toyroom: engine of world '%s' through the gateway (%s clock)" % [world_name, clock])


func _on_lost(reason: String) -> void:
	printerr("toyroom: %s; connecting again" % reason)


func _on_info(qid: int, hello) -> void:
	if hello != null and typeof(hello) == TYPE_DICTIONARY and hello.has("protocol") and major(hello["protocol"]) != major(PROTOCOL):
		link.reply(qid, error("version_mismatch", "this engine speaks %s, the client %s" % [PROTOCOL, hello["protocol"]]), false)
		return
	link.reply(qid, game.engine_info(world_name, clock))


func _on_control(qid: int, request) -> void:
	if typeof(request) != TYPE_DICTIONARY:
		link.reply(qid, error("bad_request", "engine/control takes a reset, step, pause or resume message, got %s" % ("no payload" if request == null else "a " + _type_name(request))), false)
		return
	if request.has("protocol") and major(request["protocol"]) != major(PROTOCOL):
		link.reply(qid, error("version_mismatch", "this engine speaks %s, the client %s" % [PROTOCOL, request["protocol"]]), false)
		return
	var kind = request.get("type")
	match kind:
		"reset":
			var scenario = request.get("scenario")
			if scenario != null and typeof(scenario) != TYPE_STRING:
				link.reply(qid, error("bad_request", "reset: scenario must be a string or null"), false)
				return
			var why: String = game.reset(scenario)
			if why != "":
				link.reply(qid, error("unknown_scenario", why), false)
				return
			_on_reset()
			var state: Dictionary = game.state()
			link.put("engine/state", state)
			link.reply(qid, control_reply(state, [], []))
		"step":
			var n = request.get("n", 1)
			if not (typeof(n) == TYPE_INT and n >= 1 and n <= 1000000):
				link.reply(qid, error("bad_request", "step: n must be an integer in [1, 1000000], got %s" % str(n)), false)
				return
			_step(qid, n)
		"pause", "resume":
			_pause(qid, kind == "pause")
		_:
			link.reply(qid, error("bad_request", "engine/control takes reset, step, pause or resume, got '%s'" % str(kind)), false)


static func _type_name(value) -> String:
	return ["null", "bool", "number", "number", "string"][typeof(value)] if typeof(value) <= TYPE_STRING else "list" if typeof(value) == TYPE_ARRAY else "value"


func control_reply(state: Dictionary, events: Array, statuses: Array) -> Dictionary:
	return {
		"type": "control_reply", "protocol": PROTOCOL, "episode": game.episode(), "tick": state["tick"],
		"time": state["time"], "paused": paused, "state": state, "events": events, "statuses": statuses,
	}


func publish_tick(result: Dictionary) -> void:
	# A tick's events, then its command statuses, then its state (the protocol's order).
	for event in result["events"]:
		link.put("engine/events", event)
	publish_statuses(result["statuses"])
	link.put("engine/state", result["state"])


func publish_statuses(statuses: Array) -> void:
	for status in statuses:
		link.put("robot/%s/status" % status["robot"], status)


func _on_command(key: String, command) -> void:
	_heard()
	if typeof(command) != TYPE_DICTIONARY or command.get("type") != "robot_command":
		printerr("toyroom: dropped a message on %s: not a robot_command" % key)
		return
	_command(command)


func _command(command: Dictionary) -> void:
	publish_statuses(game.command(command))


func _on_heartbeat(_key: String, _beat) -> void:
	_heard()


# ----- what each clock does its own way ------------------------------------------------------


func _heard() -> void:
	pass


func _on_reset() -> void:
	pass


func _step(qid: int, _n: int) -> void:
	link.reply(qid, error("unsupported", "step needs a lock-step engine; this one runs in real time"), false)


func _pause(qid: int, pause: bool) -> void:
	paused = pause
	link.reply(qid, control_reply(game.state(), [], []))
