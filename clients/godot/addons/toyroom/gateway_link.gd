extends Node
# The link to `toyroom gateway` (the autoload `Toyroom`): JSON frames over a WebSocket
# (protocol/README.md, "The gateway's frames"), with Godot 3's WebSocketClient.
#
#   Toyroom.open("ws://127.0.0.1:7448", "engine", "godot")
#   Toyroom.serve("engine/info", self, "_on_info")            # handler(qid, payload)
#   Toyroom.subscribe("robot/*/command", self, "_on_command")  # handler(key, payload)
#   Toyroom.put("engine/state", state)
#   Toyroom.reply(qid, control_reply)                          # or reply(qid, error, false)
#
# The link polls the socket every frame (so WebSocket pings are answered: the gateway takes a
# client that answers none for 1 s for lost), says hello, and serves and subscribes again after
# every (re)connection. When the socket drops it tries again every `retry_seconds`. Frames sent
# while a query or sample is handled (or between begin_batch() and end_batch()) go out as one
# `batch` frame: a tick's events, statuses, state and the step's reply in one message.

signal welcomed(welcome)  # the gateway accepted the hello (again, after a reconnection)
signal lost(reason)  # the socket closed or could not open; the link tries again
signal refused(frame)  # the gateway answered a frame with an `error` frame

const Json = preload("res://addons/toyroom/json_writer.gd")
const CLIENT := "toyroom-godot 0.1"
const BUFFER_KB := 16384  # a scene description and a long step's batch fit

var url := ""
var role := "engine"
var node_name := "godot"
var token = null
var retry_seconds := 0.5
var welcome = null  # the welcome frame while connected, else null
var connected_since := -1  # OS.get_ticks_msec() of the last welcome

var _client: WebSocketClient = null
var _phase := "closed"  # closed, connecting, hello, open
var _retry_in := 0.0
var _ids := 0
var _serves := {}  # id -> {key, target, method}
var _subs := {}  # id -> {key, target, method}
var _held := []  # frames (JSON text) waiting for end_batch()
var _batching := 0


func _ready() -> void:
	pause_mode = PAUSE_MODE_PROCESS  # a paused game still answers its brain


func open(gateway_url: String, gateway_role := "engine", name := "godot", hello_token = null) -> void:
	# Connect (and keep connecting) to the gateway at `gateway_url` as `gateway_role`/`name`.
	url = gateway_url
	role = gateway_role
	node_name = name
	token = hello_token
	_connect()


func close() -> void:
	url = ""
	if _client != null:
		_client.disconnect_from_host(1000, "closing")
	_phase = "closed"
	welcome = null


func is_open() -> bool:
	return _phase == "open"


func serve(key: String, target: Object, method: String) -> int:
	# Answer queries on `key` (relative to the world): target.method(qid, payload).
	return _declare("serve", _serves, key, target, method)


func subscribe(key: String, target: Object, method: String) -> int:
	# Every message on `key` (wildcards allowed): target.method(key, payload).
	return _declare("subscribe", _subs, key, target, method)


func _declare(op: String, table: Dictionary, key: String, target: Object, method: String) -> int:
	# Keep a serve or a subscription in `table` (declared again after every reconnection) and
	# declare it now when the link is open; its id.
	_ids += 1
	table[_ids] = {"key": key, "target": target, "method": method}
	if is_open():
		send({"op": op, "id": _ids, "key": key})
	return _ids


func put(key: String, payload: Dictionary) -> void:
	send({"op": "put", "key": key, "payload": payload})


func reply(qid: int, payload: Dictionary, ok := true) -> void:
	send({"op": "reply", "qid": qid, "ok": ok, "payload": payload})


func begin_batch() -> void:
	_batching += 1


func end_batch() -> void:
	_batching -= 1
	if _batching > 0 or _held.empty():
		return
	var held := _held
	_held = []
	if held.size() == 1:
		_write(held[0])
	else:
		_write("{\"op\":\"batch\",\"frames\":[" + PoolStringArray(held).join(",") + "]}")


func send(frame: Dictionary) -> void:
	# Send one frame now, or hold it for the batch being made. Dropped while disconnected
	# (the gateway forgot the queries and subscriptions of the old connection anyway).
	var text := Json.write(frame)
	if _batching > 0:
		_held.append(text)
	else:
		_write(text)


# ----- the socket --------------------------------------------------------------------------


func _connect() -> void:
	if url == "":
		return
	_client = WebSocketClient.new()
	_client.set_buffers(BUFFER_KB, 4096, BUFFER_KB, 4096)
	_client.connect("connection_established", self, "_on_established")
	_client.connect("connection_error", self, "_on_down", ["cannot connect to " + url])
	_client.connect("connection_closed", self, "_on_closed")
	_client.connect("data_received", self, "_on_data")
	var err := _client.connect_to_url(url)
	if err != OK:
		_on_down("cannot connect to %s (error %d)" % [url, err])
		return
	_phase = "connecting"


func _process(delta: float) -> void:
	poll()
	if _phase == "closed" and url != "":
		_retry_in -= delta
		if _retry_in <= 0.0:
			_connect()


func poll() -> void:
	# Read and act on what came (also answers pings); safe to call more often than per frame.
	if _client != null and _phase != "closed":
		_client.poll()


func _write(text: String) -> void:
	if _client == null or not (_phase == "open" or _phase == "hello"):
		return
	var err := _client.get_peer(1).put_packet(text.to_utf8())
	if err != OK:
		printerr("toyroom: could not send a frame of %d bytes (error %d)" % [text.length(), err])


func _on_established(_protocol: String) -> void:
	_client.get_peer(1).set_write_mode(WebSocketPeer.WRITE_MODE_TEXT)
	_phase = "hello"
	_write(Json.write({
		"op": "hello", "role": role, "name": node_name, "token": token, "frames": "1", "client": CLIENT,
	}))


func _on_closed(_clean: bool) -> void:
	_on_down("the gateway closed the connection")


func _on_down(reason: String) -> void:
	var was := _phase
	_phase = "closed"
	welcome = null
	_held = []
	_batching = 0
	_retry_in = retry_seconds
	if was != "closed":
		emit_signal("lost", reason)


func _on_data() -> void:
	var peer := _client.get_peer(1)
	while _phase != "closed" and peer.get_available_packet_count() > 0:
		var text := peer.get_packet().get_string_from_utf8()
		var got = Json.read(text)
		if got[1] != "" or typeof(got[0]) != TYPE_DICTIONARY:
			printerr("toyroom: the gateway sent a frame that is not a JSON object: ", text.substr(0, 200))
			continue
		_on_frame(got[0])


func _on_frame(frame: Dictionary) -> void:
	var op = frame.get("op")
	if _phase == "hello":
		if op != "welcome":
			printerr("toyroom: the gateway refused the hello: ", frame.get("message", frame))
			return
		_phase = "open"
		welcome = frame
		connected_since = OS.get_ticks_msec()
		begin_batch()
		for id in _serves:
			send({"op": "serve", "id": id, "key": _serves[id]["key"]})
		for id in _subs:
			send({"op": "subscribe", "id": id, "key": _subs[id]["key"]})
		end_batch()
		emit_signal("welcomed", frame)
		return
	match op:
		"query":
			var serve = _serves.get(frame.get("serve"))
			if serve == null:
				return
			begin_batch()
			serve["target"].call(serve["method"], int(frame.get("qid", 0)), frame.get("payload"))
			end_batch()
		"sample":
			var sub = _subs.get(frame.get("sub"))
			if sub == null:
				return
			begin_batch()
			sub["target"].call(sub["method"], str(frame.get("key", "")), frame.get("payload"))
			end_batch()
		"error":
			printerr("toyroom: the gateway refused a frame (%s): %s" % [frame.get("code"), frame.get("message")])
			emit_signal("refused", frame)
