extends "res://addons/toyroom/engine_host.gd"
# Lock-step: the world advances only on `step n`, and the step is answered only after the
# world has run its n ticks, each published as it is run (events, statuses, state), the reply
# carrying the last state and every event and status of the step. The ticks run in
# _process, at most `ticks_per_frame` a frame, so a long step never stops the link from
# polling (and answering the gateway's pings). A command that arrives during a step is taken
# after it, so its first status never falls inside the step.

var ticks_per_frame := 200
var _steps := []  # {qid, left, events, statuses}, oldest first
var _held_commands := []


func _ready() -> void:
	clock = "lockstep"


func _step(qid: int, n: int) -> void:
	_steps.append({"qid": qid, "left": n, "events": [], "statuses": []})


func _command(command: Dictionary) -> void:
	if _steps.empty():
		._command(command)
	else:
		_held_commands.append(command)


func _on_reset() -> void:
	_steps = []  # a reset ends the episode: steps asked before it are answered with its state
	_held_commands = []


func _on_lost(reason: String) -> void:
	._on_lost(reason)
	_steps = []  # their queries went with the connection
	_held_commands = []


func _process(_delta: float) -> void:
	var budget := ticks_per_frame
	while not _steps.empty() and budget > 0:
		var step: Dictionary = _steps[0]
		var result: Dictionary = game.tick()
		budget -= 1
		step["left"] -= 1
		step["events"] += result["events"]
		step["statuses"] += result["statuses"]
		link.begin_batch()
		publish_tick(result)
		if step["left"] == 0:
			_steps.pop_front()
			link.reply(step["qid"], control_reply(result["state"], step["events"], step["statuses"]))
			if _steps.empty():
				for command in _held_commands:
					._command(command)
				_held_commands = []
		link.end_batch()
