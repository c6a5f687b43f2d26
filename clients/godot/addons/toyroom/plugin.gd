tool
extends EditorPlugin
# Enabling the add-on registers its gateway link as the autoload `Toyroom`.

const AUTOLOAD := "Toyroom"


func _enter_tree() -> void:
	add_autoload_singleton(AUTOLOAD, "res://addons/toyroom/gateway_link.gd")


func _exit_tree() -> void:
	remove_autoload_singleton(AUTOLOAD)
