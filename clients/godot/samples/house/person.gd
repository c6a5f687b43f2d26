extends Reference
# A scripted person: their route (the scenario's script, durations in engine ticks), where
# they are in it, and how they answer the robot.

var id := ""
var wants = null
var answers := false
var plan := []
var index := 0
var started := false
var left := 0


func _init(spec: Dictionary, scenario, tick_seconds: float) -> void:
	id = spec["id"]
	wants = spec.get("wants")
	answers = spec.get("answers", false) == true
	for step in spec.get("script", []):
		var copy: Dictionary = step.duplicate(true)
		if copy.has("ticks"):
			copy["ticks"] = scenario.scaled(copy["ticks"], tick_seconds)
		plan.append(copy)


func finished() -> bool:
	# Done with the script, or in its last open-ended play, use or wait.
	if index >= plan.size():
		return true
	var step: Dictionary = plan[index]
	return started and step["do"] in ["play", "use", "wait"] and not step.has("ticks") and not step.has("until")


func replace(steps: Array) -> void:
	plan = steps
	index = 0
	started = false
