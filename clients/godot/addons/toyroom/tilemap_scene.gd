extends Reference
# The protocol's scene description (`engine_info.scene`: regions, doors, locations,
# visibility) from a TileMap, and a TileMap built from one.
#
# A map is a TileMap whose tiles name regions: a tile named after a region's id is a cell of
# that region, a tile named `door` a door cell. Protocol rows grow upwards and Godot's y
# downwards, so protocol cell (col, row) is tile (col, rows - 1 - row). The TileMap carries:
#   metadata  map_name, cell_size (metres per cell), origin ({x, y} metres), columns, rows
#   Regions/<id>  (a Node per region, optional) metadata kind (default "room"), title (the
#                 region's name) and sees (the region ids whose spots its cells see; default:
#                 its own)
#   Doors/<id>    (a Position2D per door on its cell) metadata joins (default: the regions of
#                 its neighbouring cells) and sees (default: the regions it joins)
#   Spots/<id>    (a Position2D per item location on its cell) metadata play, use, capacity
# A spot's region is the region of its cell. Each walkable cell sees the spots of the regions
# its region (or door) sees, in the order of the Spots children.

const DOOR := "door"
const PIXELS := 32


static func tile_of(cell: Vector2, rows: int) -> Vector2:
	return Vector2(cell.x, rows - 1 - cell.y)


static func cell_of(tile: Vector2, rows: int) -> Vector2:
	return Vector2(tile.x, rows - 1 - tile.y)


static func as_cell(cell: Vector2) -> Dictionary:
	return {"col": int(cell.x), "row": int(cell.y)}


static func _sorted_cells(cells: Array) -> Array:
	# By column, then row (the order sim2d's exports list them in).
	var by_key := {}
	for cell in cells:
		by_key[int(cell.x) * 100000 + int(cell.y)] = cell
	var keys := by_key.keys()
	keys.sort()
	var out := []
	for key in keys:
		out.append(by_key[key])
	return out


static func _meta(node: Node, name: String, default):
	return node.get_meta(name) if node != null and node.has_meta(name) else default


static func export_scene(map: TileMap) -> Dictionary:
	# The scene's map part: name, cell_size, origin, columns, rows, regions, doors, locations,
	# visibility (add agents and items for an engine_info).
	var rows: int = _meta(map, "rows", int(map.get_used_rect().end.y))
	var columns: int = _meta(map, "columns", int(map.get_used_rect().end.x))
	var tiles: TileSet = map.tile_set
	var region_at := {}  # cell -> region id
	var regions := []
	var door_tile := -1
	var ids := Array(tiles.get_tiles_ids())
	ids.sort()
	for tile in ids:
		var id := tiles.tile_get_name(tile)
		if id == DOOR:
			door_tile = tile
			continue
		var cells := []
		for t in map.get_used_cells_by_id(tile):
			var cell := cell_of(t, rows)
			cells.append(cell)
			region_at[cell] = id
		var node := map.get_node_or_null("Regions/" + id)
		var out_cells := []
		for cell in _sorted_cells(cells):
			out_cells.append(as_cell(cell))
		regions.append({"id": id, "kind": _meta(node, "kind", "room"), "cells": out_cells, "name": _meta(node, "title", "")})
	var spots := []
	var spot_region := {}
	var folder := map.get_node_or_null("Spots")
	for spot in (folder.get_children() if folder != null else []):
		var cell := cell_of(map.world_to_map(spot.position), rows)
		var region = region_at.get(cell)
		spot_region[spot.name] = region
		spots.append({
			"id": spot.name, "region": region, "cell": as_cell(cell), "play": _meta(spot, "play", false),
			"use": _meta(spot, "use", false), "capacity": _meta(spot, "capacity", null),
		})
	var sees := {}  # cell -> region ids seen
	for region in regions:
		var node := map.get_node_or_null("Regions/" + region["id"])
		var seen = _meta(node, "sees", [region["id"]])
		for c in region["cells"]:
			sees[Vector2(c["col"], c["row"])] = seen
	var doors := []
	folder = map.get_node_or_null("Doors")
	var door_cells := {}
	for door in (folder.get_children() if folder != null else []):
		var cell := cell_of(map.world_to_map(door.position), rows)
		var joins = _meta(door, "joins", null)
		if joins == null:
			joins = []
			for region in regions:
				for step in [Vector2(1, 0), Vector2(-1, 0), Vector2(0, 1), Vector2(0, -1)]:
					if region_at.get(cell + step) == region["id"] and not region["id"] in joins:
						joins.append(region["id"])
		doors.append({"id": door.name, "cell": as_cell(cell), "joins": Array(joins)})
		sees[cell] = _meta(door, "sees", joins)
		door_cells[cell] = true
	if door_tile >= 0:
		for t in map.get_used_cells_by_id(door_tile):
			var cell := cell_of(t, rows)
			if not door_cells.has(cell):  # a door tile without a Doors node: a nameless door
				var name := "door-%d-%d" % [int(cell.x), int(cell.y)]
				doors.append({"id": name, "cell": as_cell(cell), "joins": []})
				sees[cell] = []
	var visibility := []
	for cell in _sorted_cells(sees.keys()):
		var seen := []
		for spot in spots:
			if spot_region[spot["id"]] in sees[cell]:
				seen.append(spot["id"])
		visibility.append({"cell": as_cell(cell), "locations": seen})
	return {
		"name": _meta(map, "map_name", map.name), "cell_size": float(_meta(map, "cell_size", 1.0)),
		"origin": _meta(map, "origin", {"x": 0.0, "y": 0.0}), "columns": columns, "rows": rows,
		"regions": regions, "doors": doors, "locations": spots, "visibility": visibility,
	}


static func build(map: TileMap, scene: Dictionary) -> Array:
	# Fill `map` (tiles, metadata, Regions, Doors, Spots) from a protocol scene; the list of
	# what a TileMap cannot say of it (empty: export_scene(map) gives the scene back).
	var problems := []
	var rows: int = scene["rows"]
	map.clear()
	map.cell_size = Vector2(PIXELS, PIXELS)
	map.set_meta("map_name", scene["name"])
	map.set_meta("cell_size", scene["cell_size"])
	map.set_meta("origin", scene["origin"])
	map.set_meta("columns", scene["columns"])
	map.set_meta("rows", rows)
	for folder in ["Regions", "Doors", "Spots"]:
		var old := map.get_node_or_null(folder)
		if old != null:
			map.remove_child(old)
			old.free()
	var tiles := TileSet.new()
	var regions_node := Node.new()
	regions_node.name = "Regions"
	map.add_child(regions_node)
	var spot_region := {}
	for location in scene["locations"]:
		spot_region[location["id"]] = location["region"]
	var seen_at := {}
	for entry in scene["visibility"]:
		seen_at[Vector2(entry["cell"]["col"], entry["cell"]["row"])] = entry["locations"]
	var tile := 0
	for region in scene["regions"]:
		tiles.create_tile(tile)
		tiles.tile_set_name(tile, region["id"])
		var node := Node.new()
		node.name = region["id"]
		node.set_meta("kind", region["kind"])
		node.set_meta("title", region.get("name", ""))
		regions_node.add_child(node)
		var view = null
		for c in region["cells"]:
			var cell := Vector2(c["col"], c["row"])
			var tile_cell := tile_of(cell, rows)
			map.set_cell(int(tile_cell.x), int(tile_cell.y), tile)
			var seen = seen_at.get(cell, [])
			if view == null:
				view = seen
			elif str(seen) != str(view):
				problems.append("cell %s of region '%s' sees %s, unlike the rest of its region (%s)" % [c, region["id"], seen, view])
		var by_region = _regions_seen(view if view != null else [], spot_region)
		if str(by_region) != str([region["id"]]):
			node.set_meta("sees", by_region)
		tile += 1
	tiles.create_tile(tile)
	tiles.tile_set_name(tile, DOOR)
	map.tile_set = tiles
	var doors_node := Node2D.new()
	doors_node.name = "Doors"
	map.add_child(doors_node)
	for door in scene["doors"]:
		var cell := Vector2(door["cell"]["col"], door["cell"]["row"])
		var tile_cell := tile_of(cell, rows)
		map.set_cell(int(tile_cell.x), int(tile_cell.y), tile)
		var node := Position2D.new()
		node.name = door["id"]
		node.position = map.map_to_world(tile_cell) + map.cell_size / 2
		node.set_meta("joins", door["joins"])
		var by_region = _regions_seen(seen_at.get(cell, []), spot_region)
		if str(by_region) != str(door["joins"]):
			node.set_meta("sees", by_region)
		doors_node.add_child(node)
	var spots_node := Node2D.new()
	spots_node.name = "Spots"
	map.add_child(spots_node)
	for location in scene["locations"]:
		var node := Position2D.new()
		node.name = location["id"]
		node.position = map.map_to_world(tile_of(Vector2(location["cell"]["col"], location["cell"]["row"]), rows)) + map.cell_size / 2
		node.set_meta("play", location.get("play", false))
		node.set_meta("use", location.get("use", false))
		if location.get("capacity") != null:
			node.set_meta("capacity", location["capacity"])
		spots_node.add_child(node)
	return problems


static func _regions_seen(seen: Array, spot_region: Dictionary) -> Array:
	var out := []
	for id in seen:
		var region = spot_region.get(id)
		if region != null and not region in out:
			out.append(region)
	return out


static func same_map(a: Dictionary, b: Dictionary) -> String:
	# "" when two scenes have the same map (regions' cells in any order), else the first
	# difference, as JSON.
	var Json = load("res://addons/toyroom/json_writer.gd")
	for key in ["name", "cell_size", "origin", "columns", "rows", "regions", "doors", "locations", "visibility"]:
		var left = a.get(key)
		var right = b.get(key)
		if key == "regions":
			left = _cells_sorted(left)
			right = _cells_sorted(right)
		var lt: String = Json.write(left)
		var rt: String = Json.write(right)
		if lt != rt:
			return "%s differ: %s against %s" % [key, lt.substr(0, 300), rt.substr(0, 300)]
	return ""


static func _cells_sorted(regions: Array) -> Array:
	var out := []
	for region in regions:
		var copy: Dictionary = region.duplicate(true)
		var cells := []
		for c in region["cells"]:
			cells.append(Vector2(c["col"], c["row"]))
		copy["cells"] = []
		for cell in _sorted_cells(cells):
			copy["cells"].append(as_cell(cell))
		out.append(copy)
	return out
