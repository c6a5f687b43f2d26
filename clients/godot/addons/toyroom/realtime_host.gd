extends "res://addons/toyroom/engine_host.gd"
# Real time: a Timer ticks the world every tick_seconds / rate of wall-clock time and publishes
# each tick; `pause` stops the timer, `resume` starts it again, `step` is refused
# (`unsupported`). The heartbeat watchdog: when neither a heartbeat nor a command has come
# for `heartbeat_timeout` seconds, the robot stops and its commands fail with the reason, as
# sim2d does (a brain that dies never leaves a robot driving).

var rate := 1.0
var heartbeat_timeout := 1.0
var timer: Timer
var _last_heard := 0


func _ready() -> void:
	clock = "realtime"
	_last_heard = OS.get_ticks_msec()
	timer = Timer.new()
	timer.name = "Clock"
	timer.process_mode = Timer.TIMER_PROCESS_PHYSICS
	add_child(timer)
	timer.connect("timeout", self, "_on_tick")


func start(gateway_link, the_game) -> void:
	.start(gateway_link, the_game)
	timer.wait_time = max(0.001, game.tick_seconds() / rate)
	timer.start()


func _heard() -> void:
	_last_heard = OS.get_ticks_msec()


func watchdog() -> void:
	var silent := (OS.get_ticks_msec() - _last_heard) / 1000.0
	if silent > heartbeat_timeout:
		var stopped: Array = game.stop_robot("stopped: no heartbeat or command from the brain for %.1f s" % silent)
		if not stopped.empty():
			printerr("toyroom: the brain has been silent for %.1f s: robot stopped" % silent)
			link.begin_batch()
			publish_statuses(stopped)
			link.end_batch()


func _on_tick() -> void:
	if paused:
		return
	watchdog()
	var result: Dictionary = game.tick()
	link.begin_batch()
	publish_tick(result)
	link.end_batch()


func _pause(qid: int, pause: bool) -> void:
	paused = pause
	timer.paused = pause
	if not pause:
		timer.start()  # the next tick a whole period from now
	link.reply(qid, control_reply(game.state(), [], []))


func _on_reset() -> void:
	timer.start()
