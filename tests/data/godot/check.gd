extends SceneTree
# Loads every frames/*.tscn and prints its Polygon2D's arrays as JSON.
func _init():
    var out = {}
    var dir = Directory.new()
    dir.open("res://frames")
    dir.list_dir_begin(true, true)
    var name = dir.get_next()
    while name != "":
        if name.ends_with(".tscn"):
            var s = load("res://frames/" + name)
            if s == null:
                print("LOAD FAILED " + name)
                quit(1)
                return
            var n = s.instance()
            var polygon = []
            for v in n.polygon:
                polygon.append([v.x, v.y])
            var uv = []
            for v in n.uv:
                uv.append([v.x, v.y])
            var polygons = []
            for p in n.polygons:
                polygons.append(Array(p))
            out[name] = {"class": n.get_class(), "polygon": polygon, "uv": uv, "polygons": polygons, "texture": n.texture.resource_path if n.texture else ""}
            n.free()
        name = dir.get_next()
    print("GODOT_RESULT " + JSON.print(out))
    quit(0)
