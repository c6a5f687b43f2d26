extends Reference
# JSON for the toyroom protocol from Godot 3.
#
# Godot 3's parse_json / JSON.parse return every number as a float, and its JSON.print writes
# floats with 6 significant digits and an integral float without a point. The protocol wants
# integers where the schema says `integer` (`"tick": 42`; `42.0` is refused as "Expected
# 'int', got 'float'") and floats exact enough to compare. So: `read()` parses and turns
# every field the schemas call an integer back into an int (INT_FIELDS), and `write()` writes
# an int as an integer and a float always with a point and up to 9 decimals.

# Every field name that the protocol's and the gateway's JSON Schemas type `integer`
# (protocol/schema/**.json); frames' `id` is an int, a robot command's `id` a string.
const INT_FIELDS := {
	"capacity": true, "col": true, "columns": true, "day": true, "episode": true, "id": true,
	"n": true, "qid": true, "ref": true, "row": true, "rows": true, "seed": true, "seq": true,
	"serve": true, "sub": true, "tick": true,
}


static func read(text: String):
	# [the JSON value of `text` with integer fields as ints, ""], or [null, why] when
	# `text` is not JSON.
	var parsed := JSON.parse(text)
	if parsed.error != OK:
		return [null, "not JSON: %s at line %d" % [parsed.error_string, parsed.error_line]]
	return [ints(parsed.result), ""]


static func ints(value, key := ""):
	# `value` with every integral float under an INT_FIELDS key turned into an int.
	match typeof(value):
		TYPE_DICTIONARY:
			var out := {}
			for k in value:
				out[k] = ints(value[k], str(k))
			return out
		TYPE_ARRAY:
			var out := []
			for item in value:
				out.append(ints(item, key))
			return out
		TYPE_REAL:
			if INT_FIELDS.has(key) and value == floor(value) and abs(value) < 9.0e15:
				return int(value)
	return value


static func write(value) -> String:
	# `value` as compact JSON: ints as integers, floats with a point (`0.7`, `1.0`), null,
	# bools, strings escaped, arrays and dictionaries (keys in insertion order).
	match typeof(value):
		TYPE_NIL:
			return "null"
		TYPE_BOOL:
			return "true" if value else "false"
		TYPE_INT:
			return str(value)
		TYPE_REAL:
			return number(value)
		TYPE_STRING:
			return quote(value)
		TYPE_ARRAY, TYPE_STRING_ARRAY, TYPE_INT_ARRAY, TYPE_REAL_ARRAY:
			var parts := PoolStringArray()
			for item in value:
				parts.append(write(item))
			return "[" + parts.join(",") + "]"
		TYPE_DICTIONARY:
			var parts := PoolStringArray()
			for k in value:
				parts.append(quote(str(k)) + ":" + write(value[k]))
			return "{" + parts.join(",") + "}"
	return quote(str(value))


static func number(x: float) -> String:
	# A float with a decimal point and at most 9 decimals (as Python's round(x, 9)).
	if is_nan(x) or is_inf(x):
		return "null"  # JSON has no NaN; the protocol never sends one
	var text := "%.9f" % x
	text = text.rstrip("0")
	if text.ends_with("."):
		text += "0"
	if text == "-0.0":
		text = "0.0"
	return text


static func quote(text: String) -> String:
	var out := "\""
	for i in range(text.length()):
		var c := text.ord_at(i)
		match c:
			34:
				out += "\\\""
			92:
				out += "\\\\"
			10:
				out += "\\n"
			13:
				out += "\\r"
			9:
				out += "\\t"
			_:
				if c < 32:
					out += "\\u%04x" % c
				else:
					out += char(c)
	return out + "\""
