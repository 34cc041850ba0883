// Tiled layers -> elements, in the order Tiled draws them: layers in file
// order (groups recursively), the cells of a tile layer in the map's
// renderorder on orthogonal maps and in screen raster order on the others
// (isometric: by col + row, then col; staggered / hexagonal: by the cell's
// top edge, then left to right), objects of an object group sorted by y
// (draworder "topdown", the default) or in file order ("index").
//
// Placement follows Tiled's CellRenderer: a tile is drawn with its
// bottom-left at the bottom-left of its cell (a tile taller than the grid
// reaches upward), shifted by the tileset's tileoffset; flips mirror it
// about its centre; the anti-diagonal flip is a 90-degree clockwise turn
// plus a vertical flip, keeping the bottom edge in place. A tile object's
// (x, y) is its alignment point (bottom-left on orthogonal maps, bottom
// centre on isometric ones), width/height scale the tile, and rotation
// turns it clockwise about (x, y).
//
// Not drawn: shapes, points and text of object layers (games do not draw
// them as images) and parallax factors (a static picture of the map, as
// Tiled's tmxrasterizer draws it).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <cstdio>
#include <numbers>

#include "io/tiled_internal.h"

namespace depthcull::io::tiled {

namespace {

using Affine = std::array<double, 6>;

// a o b: apply b, then a.
Affine compose(const Affine& a, const Affine& b) {
    return {a[0] * b[0] + a[2] * b[1],        a[1] * b[0] + a[3] * b[1],        a[0] * b[2] + a[2] * b[3],
            a[1] * b[2] + a[3] * b[3],        a[0] * b[4] + a[2] * b[5] + a[4], a[1] * b[4] + a[3] * b[5] + a[5]};
}

// Clockwise (y down) rotation by `degrees` about (px, py). Multiples of 90
// are exact so axis-aligned results stay on the pixel grid.
Affine rotation_about(double degrees, double px, double py) {
    double turns = degrees / 90.0;
    double c, s;
    if (turns == std::floor(turns)) {
        static const double cs[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
        int q = int(std::fmod(std::fmod(turns, 4.0) + 4.0, 4.0));
        c = cs[q][0];
        s = cs[q][1];
    } else {
        double r = degrees * std::numbers::pi / 180.0;
        c = std::cos(r);
        s = std::sin(r);
    }
    return {c, s, -s, c, px - c * px + s * py, py - s * px - c * py};
}

// The tile's texels (w x h) drawn into the box [x, x+bw] x [y, y+bh] with
// the gid's flips, as Tiled's CellRenderer does. `bottom_fixed`: the
// anti-diagonal turn keeps the box's bottom edge and horizontal centre
// (tile layers); otherwise it keeps the centre (objects).
Affine place_in_box(double w, double h, double x, double y, double bw, double bh, std::uint32_t flags, bool bottom_fixed) {
    bool flip_h = flags & kFlipHorizontal, flip_v = flags & kFlipVertical;
    double sx = bw / w, sy = bh / h;
    double cx = x + bw / 2, cy = y + bh / 2;
    Affine m;
    if (flags & kFlipDiagonal) {
        bool h2 = flip_v, v2 = !flip_h;
        double fx = h2 ? -sx : sx, fy = v2 ? -sy : sy;
        m = {0, fx, -fy, 0, 0, 0}; // R90 * diag(fx, fy)
        double half_diff = bh / 2 - bw / 2;
        cy += half_diff;
        if (!bottom_fixed) cy -= half_diff;
    } else {
        m = {flip_h ? -sx : sx, 0, 0, flip_v ? -sy : sy, 0, 0};
    }
    m[4] = cx - (m[0] * w / 2 + m[2] * h / 2);
    m[5] = cy - (m[1] * w / 2 + m[3] * h / 2);
    return m;
}

double clamp01(double v) { return v < 0 ? 0 : v > 1 ? 1 : v; }

} // namespace

std::array<double, 4> parse_color(const std::string& text, const std::string& where) {
    std::string_view hex = text;
    if (!hex.empty() && hex[0] == '#') hex.remove_prefix(1);
    if (hex.size() != 6 && hex.size() != 8) throw Error(where + ": colour '" + text + "' is not #RRGGBB or #AARRGGBB");
    std::uint32_t v = 0;
    for (char ch : hex) {
        int d = ch >= '0' && ch <= '9' ? ch - '0' : ch >= 'a' && ch <= 'f' ? ch - 'a' + 10 : ch >= 'A' && ch <= 'F' ? ch - 'A' + 10 : -1;
        if (d < 0) throw Error(where + ": colour '" + text + "' is not #RRGGBB or #AARRGGBB");
        v = v << 4 | std::uint32_t(d);
    }
    double a = hex.size() == 8 ? double(v >> 24) / 255.0 : 1.0;
    return {double((v >> 16) & 255) / 255.0, double((v >> 8) & 255) / 255.0, double(v & 255) / 255.0, a};
}

void warn(Emitter& out, const std::string& line) {
    if (out.options && out.options->strict) throw Error(line + " (--strict)");
    if (!out.warned.insert(line).second) return;
    if (out.options && out.options->warning) out.options->warning(line);
}

int animation_of(Emitter& out, const Tileset& tileset, std::uint32_t local, const std::string& where) {
    if (auto w = tileset.tables->animation_warnings.find(local); w != tileset.tables->animation_warnings.end())
        warn(out, where + ": animated tile " + std::to_string(local) + " of tileset '" + tileset.name + "': " + w->second);
    auto it = tileset.tables->animations.find(local);
    if (it == tileset.tables->animations.end()) return -1;
    auto [slot, fresh] = out.animation_index.try_emplace({&tileset, local}, -1);
    if (!fresh) return slot->second;
    const auto& frames = it->second;
    Animation animation;
    for (const auto& [tile, duration] : frames) {
        if (tile.rect.w != frames.front().first.rect.w || tile.rect.h != frames.front().first.rect.h) {
            warn(out, where + ": animated tile " + std::to_string(local) + " of tileset '" + tileset.name +
                          "' has frames of different sizes: drawn at its first frame, not animated");
            return -1;
        }
        animation.frames.push_back({tile.image, tile.rect, duration});
    }
    slot->second = int(out.scene.animations.size());
    out.scene.animations.push_back(std::move(animation));
    return slot->second;
}

void note(Emitter& out, const std::string& line) {
    if (!out.warned.insert(line).second) return;
    if (out.options && out.options->note) out.options->note(line);
}

namespace {

// Offsets, opacity and tint of `layer` on top of its parents'.
LayerState child_state(pugi::xml_node layer, const LayerState& parent, const std::string& where) {
    LayerState s = parent;
    s.offset_x += double_attr(layer, "offsetx", 0, where);
    s.offset_y += double_attr(layer, "offsety", 0, where);
    double opacity = double_attr(layer, "opacity", 1, where);
    if (!(std::fabs(s.offset_x) <= limits::kMaxCoordinate && std::fabs(s.offset_y) <= limits::kMaxCoordinate) || !std::isfinite(opacity))
        throw Error(where + ": offset or opacity is not a finite number within +-1e9 (kMaxCoordinate)");
    s.opacity *= clamp01(opacity);
    double px = double_attr(layer, "parallaxx", 1, where), py = double_attr(layer, "parallaxy", 1, where);
    if (!(std::fabs(px) <= limits::kMaxCoordinate && std::fabs(py) <= limits::kMaxCoordinate))
        throw Error(where + ": parallaxx / parallaxy is not a finite number within +-1e9 (kMaxCoordinate)");
    s.parallax_x *= px;
    s.parallax_y *= py;
    if (pugi::xml_attribute tint = layer.attribute("tintcolor")) {
        auto c = parse_color(tint.as_string(), where);
        for (int i = 0; i < 4; ++i) s.tint[std::size_t(i)] *= c[std::size_t(i)];
    }
    return s;
}

// Element colour: Tiled multiplies the texels by the tint colour blended by
// the tint's alpha (Qt's Multiply composition: 1 - a + a*c per channel).
std::array<float, 4> element_color(const LayerState& s) {
    double a = s.tint[3];
    return {float(1 - a + a * s.tint[0]), float(1 - a + a * s.tint[1]), float(1 - a + a * s.tint[2]), float(s.opacity)};
}

void push(Emitter& out, const Element& e, const std::string& where) {
    if (out.cull) {
        Box b = element_bounds(e);
        const Viewport& v = *out.cull;
        if (b.x1 <= v.x || b.y1 <= v.y || b.x0 >= v.x + v.width || b.y0 >= v.y + v.height) return;
    }
    if (std::int64_t(out.scene.elements.size()) >= kMaxElements)
        throw Error(where + ": the scene has more than " + std::to_string(kMaxElements) + " elements (kMaxMapElements; use --viewport)");
    out.scene.elements.push_back(e);
}

void emit_cell(Emitter& out, std::uint32_t raw, int col, int row, const LayerState& s, const std::array<float, 4>& color,
               const std::string& where) {
    const MapInfo& m = out.info;
    if ((raw & kRotateHex120) && !m.hex_rotation)
        throw Error(where + ": the 120-degree rotation flag is only valid on hexagonal maps");
    TileRef ref = find_tile(out.tilesets, raw & kGidMask, where);
    const Rect& r = ref.tile.rect;
    double bw = ref.tileset->render_grid_size ? m.tile_width : r.w;
    double bh = ref.tileset->render_grid_size ? m.tile_height : r.h;
    double fit_x = 0, fit_y = 0; // preserve-aspect-fit: the scaled tile centred in the cell
    if (ref.tileset->preserve_aspect) {
        const double scale = std::min(bw / r.w, bh / r.h);
        fit_x = (bw - r.w * scale) / 2;
        fit_y = (bh - r.h * scale) / 2;
        bw = r.w * scale;
        bh = r.h * scale;
    }
    // The cell's bottom-left corner on screen.
    double x, y;
    if (m.orientation == Orientation::orthogonal) {
        x = double(col) * m.tile_width;
        y = double(row + 1) * m.tile_height;
    } else if (m.orientation == Orientation::hexagonal) {
        Vec2 top_left = hex_cell_top_left(m, col, row);
        x = top_left.x;
        y = top_left.y + (m.tile_height & ~1);
    } else {
        double origin_x = double(m.height) * m.tile_width / 2;
        x = double(col - row) * m.tile_width / 2 + origin_x - m.tile_width / 2.0;
        y = double(col + row) * m.tile_height / 2 + m.tile_height;
    }
    x += s.offset_x + ref.tileset->offset_x * bw / r.w + fit_x;
    y += s.offset_y + ref.tileset->offset_y * bh / r.h - fit_y;
    Element e;
    e.image = ref.tile.image;
    e.rect = r;
    std::uint32_t flags = raw & ~kGidMask;
    if (m.hex_rotation && (flags & (kFlipDiagonal | kRotateHex120))) {
        // Hexagonal maps (TMX format): the anti-diagonal bit turns the tile
        // 60 degrees clockwise, bit 28 120 degrees, about its centre, after
        // the horizontal / vertical flips.
        double degrees = ((flags & kFlipDiagonal) ? 60.0 : 0.0) + ((flags & kRotateHex120) ? 120.0 : 0.0);
        e.transform = place_in_box(r.w, r.h, x, y - bh, bw, bh, flags & (kFlipHorizontal | kFlipVertical), true);
        e.transform = compose(rotation_about(degrees, x + bw / 2, y - bh / 2), e.transform);
    } else {
        e.transform = place_in_box(r.w, r.h, x, y - bh, bw, bh, flags, true);
    }
    e.color = color;
    e.animation = animation_of(out, *ref.tileset, (raw & kGidMask) - ref.tileset->firstgid, where);
    push(out, e, where);
}

void emit_tile_layer(pugi::xml_node layer, const LayerState& s, Emitter& out, const std::string& where) {
    const MapInfo& m = out.info;
    CellGrid grid = read_layer_data(layer, int_attr(layer, "width", m.width, where), int_attr(layer, "height", m.height, where),
                                    m.infinite, where);
    out.cells += std::int64_t(grid.gids.size());
    if (out.cells > limits::kMaxMapCells)
        throw Error(where + ": the map's tile layers hold more than " + std::to_string(limits::kMaxMapCells) + " cells (kMaxMapCells)");
    auto color = element_color(s);
    auto cell = [&](int c, int r) {
        std::uint32_t gid = grid.gids[std::size_t(r) * grid.width + c];
        if (gid & kGidMask) emit_cell(out, gid, grid.x0 + c, grid.y0 + r, s, color, where);
    };
    if (m.orientation == Orientation::isometric) {
        // Tiled's IsometricRenderer draws screen rows top to bottom
        // (col + row ascending), each left to right (col ascending).
        for (int sum = 0; sum <= grid.width + grid.height - 2; ++sum)
            for (int c = std::max(0, sum - grid.height + 1); c <= std::min(grid.width - 1, sum); ++c) cell(c, sum - c);
        return;
    }
    if (m.orientation == Orientation::hexagonal) {
        // Tiled's HexagonalRenderer draws in screen raster order: by the
        // cell's top edge, then left to right (with staggeraxis x: the
        // raised columns of a row before the lowered ones).
        struct Cell {
            double y, x;
            int c, r;
        };
        std::vector<Cell> cells;
        for (int r = 0; r < grid.height; ++r)
            for (int c = 0; c < grid.width; ++c)
                if (grid.gids[std::size_t(r) * grid.width + c] & kGidMask) {
                    Vec2 p = hex_cell_top_left(m, grid.x0 + c, grid.y0 + r);
                    cells.push_back({p.y, p.x, c, r});
                }
        std::stable_sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
        for (const Cell& k : cells) cell(k.c, k.r);
        return;
    }
    bool right = m.render_order == RenderOrder::right_down || m.render_order == RenderOrder::right_up;
    bool down = m.render_order == RenderOrder::right_down || m.render_order == RenderOrder::left_down;
    for (int i = 0; i < grid.height; ++i) {
        int r = down ? i : grid.height - 1 - i;
        for (int j = 0; j < grid.width; ++j) cell(right ? j : grid.width - 1 - j, r);
    }
}

struct TileObject {
    double x = 0, y = 0, width = 0, height = 0, rotation = 0;
    std::uint32_t gid = 0;
    std::string where;
};

void emit_object(Emitter& out, const TileObject& o, const LayerState& s, const std::array<float, 4>& color) {
    const MapInfo& m = out.info;
    TileRef ref = find_tile(out.tilesets, o.gid & kGidMask, o.where);
    const Rect& r = ref.tile.rect;
    double w = o.width, h = o.height;
    if (w <= 0 || h <= 0) return; // a zero-size object draws nothing
    // The object's alignment point on screen.
    double px = o.x, py = o.y;
    if (m.orientation == Orientation::isometric) {
        double tx = o.x / m.tile_height, ty = o.y / m.tile_height;
        px = (tx - ty) * m.tile_width / 2 + double(m.height) * m.tile_width / 2;
        py = (tx + ty) * m.tile_height / 2;
    }
    px += s.offset_x;
    py += s.offset_y;
    Alignment a = ref.tileset->alignment;
    if (a == Alignment::unspecified) a = m.orientation == Orientation::isometric ? Alignment::bottom : Alignment::bottomleft;
    double ax = (a == Alignment::top || a == Alignment::center || a == Alignment::bottom) ? 0.5
                : (a == Alignment::topright || a == Alignment::right || a == Alignment::bottomright) ? 1.0 : 0.0;
    double ay = (a == Alignment::left || a == Alignment::center || a == Alignment::right) ? 0.5
                : (a == Alignment::bottomleft || a == Alignment::bottom || a == Alignment::bottomright) ? 1.0 : 0.0;
    double bx = px - ax * w + ref.tileset->offset_x * w / r.w;
    double by = py - ay * h + ref.tileset->offset_y * h / r.h;
    Element e;
    e.image = ref.tile.image;
    e.rect = r;
    e.transform = place_in_box(r.w, r.h, bx, by, w, h, o.gid & ~kGidMask, false);
    if (o.rotation != 0) e.transform = compose(rotation_about(o.rotation, px, py), e.transform);
    e.color = color;
    e.animation = animation_of(out, *ref.tileset, (o.gid & kGidMask) - ref.tileset->firstgid, o.where);
    push(out, e, o.where);
}

// An object template (.tx): its <object> gives the defaults an instance
// overrides; its gid counts in the template's own tileset, which must be
// one of the map's (matched by file), as Tiled adds it to the map.
} // namespace

// Outside the unnamed namespace: Emitter holds it by pointer.
struct Template {
    pugi::xml_document doc;
    pugi::xml_node object;
    std::uint32_t gid = 0; // translated to the map's gids; 0: not a tile object
};

namespace {

void load_template(const std::string& path, Emitter& out, const std::string& where, Template& t) {
    if (out.options && out.options->documents) out.options->documents->push_back(path);
    std::string text = read_maybe_gzipped(path);
    // Templates stay parsed while the map is read: their estimates add to
    // the map's (a JSON template's, for the document made from it).
    const bool json = looks_like_json(text);
    out.documents += json ? json_document_bytes(text, path) : xml_document_bytes(text);
    check_documents_held(out.documents, path);
    if (json) {
        json_template_to_xml(text, path, t.doc);
    } else {
        pugi::xml_parse_result ok = t.doc.load_buffer(text.data(), text.size());
        if (!ok) throw Error(path + ": XML error at byte " + std::to_string(ok.offset) + ": " + ok.description());
    }
    t.object = t.doc.child("template").child("object");
    if (!t.object) throw Error(path + ": no <template><object> element");
    std::uint32_t raw = gid_attr(t.object, "gid", path);
    if ((raw & kGidMask) == 0) return;
    pugi::xml_node ts = t.doc.child("template").child("tileset");
    if (!ts || !ts.attribute("source")) throw Error(path + ": template's tile object needs an external tileset");
    std::string tsx = resolve_tsx(std::filesystem::path(path).parent_path().string(), ts.attribute("source").as_string());
    const long long first = llong_attr(ts, "firstgid", 1, path);
    // As read_tilesets: a negative or zero firstgid would shift the gid below.
    if (first < 1 || first > kGidMask) throw Error(path + ": template's tileset firstgid out of range 1.." + std::to_string(kGidMask));
    for (const Tileset& m : out.tilesets)
        if (!m.source.empty() && std::filesystem::path(m.source) == std::filesystem::path(tsx) && (raw & kGidMask) >= first) {
            // Wider arithmetic: a large local id plus the map's firstgid
            // must not spill into the flag bits.
            std::uint64_t gid = std::uint64_t(raw & kGidMask) - first + m.firstgid;
            if (gid > kGidMask) throw Error(where + ": template " + path + ": gid " + std::to_string(gid) + " is out of range");
            t.gid = std::uint32_t(gid) | (raw & ~kGidMask);
            return;
        }
    throw Error(where + ": template " + path + " uses tileset " + tsx + ", which the map does not list");
}

// The template an object names, each file parsed once per map.
const Template& find_template(const std::string& source, Emitter& out, const std::string& where) {
    if (auto it = out.templates_by_source.find(source); it != out.templates_by_source.end()) return *it->second;
    std::string map_dir = std::filesystem::path(out.info.where).parent_path().string();
    std::string path = resolve_tsx(map_dir, source);
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(where + ": template '" + source + "' not found (" + path + ")");
    auto& by_file = out.templates_by_file[file_identity(path)];
    if (!by_file) {
        auto t = std::make_shared<Template>();
        load_template(path, out, where, *t);
        by_file = std::move(t);
    }
    out.templates_by_source.emplace(source, by_file);
    return *by_file;
}

void emit_object_group(pugi::xml_node group, const LayerState& s, Emitter& out, const std::string& where) {
    std::vector<TileObject> objects;
    for (pugi::xml_node node : group.children("object")) {
        std::string here = where + ": object " + node.attribute("id").as_string("?");
        // Attributes: the instance's, else its template's.
        pugi::xml_node base;
        std::uint32_t template_gid = 0;
        if (pugi::xml_attribute source = node.attribute("template")) {
            const Template& t = find_template(source.as_string(), out, here);
            base = t.object;
            template_gid = t.gid;
        }
        auto owner = [&](const char* name) { return node.attribute(name) ? node : base; };
        if (!visible_attr(owner("visible"), here)) continue;
        TileObject o;
        o.where = here;
        o.gid = node.attribute("gid") ? gid_attr(node, "gid", here) : template_gid;
        if ((o.gid & kGidMask) == 0) {
            // Shapes and points are editor geometry engines do not draw as
            // images; text is drawn by Tiled, not by us.
            if (node.child("text") || base.child("text")) warn(out, where + ": text objects are not drawn");
            continue;
        }
        if (o.gid & kRotateHex120) throw Error(here + ": the hexagonal 120-degree rotation flag is not supported");
        TileRef ref = find_tile(out.tilesets, o.gid & kGidMask, here);
        o.x = double_attr(node, "x", 0, here);
        o.y = double_attr(node, "y", 0, here);
        o.width = double_attr(owner("width"), "width", ref.tile.rect.w, here);
        o.height = double_attr(owner("height"), "height", ref.tile.rect.h, here);
        o.rotation = double_attr(owner("rotation"), "rotation", 0, here);
        auto in_range = [](double v) { return std::fabs(v) <= limits::kMaxCoordinate; }; // false for nan
        if (!in_range(o.x) || !in_range(o.y) || !in_range(o.width) || !in_range(o.height) || !std::isfinite(o.rotation))
            throw Error(here + ": position, size or rotation is not a finite number within +-1e9 (kMaxCoordinate)");
        objects.push_back(std::move(o));
    }
    std::string order = group.attribute("draworder").as_string("topdown");
    if (order == "topdown")
        std::stable_sort(objects.begin(), objects.end(), [](const TileObject& a, const TileObject& b) { return a.y < b.y; });
    else if (order != "index")
        throw Error(where + ": unknown draworder '" + order + "'");
    auto color = element_color(s);
    for (const TileObject& o : objects) emit_object(out, o, s, color);
}

void emit_image_layer(pugi::xml_node layer, const LayerState& s, Emitter& out, const std::string& where) {
    pugi::xml_node image = layer.child("image");
    if (!image || !image.attribute("source") || !*image.attribute("source").as_string()) return; // Tiled allows an empty image layer
    std::string dir = std::filesystem::path(out.info.where).parent_path().string();
    int index = out.images.add(dir, image.attribute("source").as_string(), image.attribute("trans").as_string(), where);
    const int w = out.images.width(index), h = out.images.height(index);
    bool repeat_x = layer.attribute("repeatx").as_int(0) != 0, repeat_y = layer.attribute("repeaty").as_int(0) != 0;
    if ((repeat_x || repeat_y) && !out.cull) {
        warn(out, where + ": repeating image layer drawn once (an infinite map needs --viewport to repeat it)");
        repeat_x = repeat_y = false;
    }
    // A repeating layer is the image tiled without end along the axis, as
    // Tiled draws it: the copies that meet the camera, in raster order.
    auto span = [](bool repeat, double origin, int side, double view0, int view_side, long long* k0, long long* k1) {
        if (!repeat) {
            *k0 = *k1 = 0;
            return;
        }
        *k0 = (long long)std::floor((view0 - origin) / side);
        *k1 = (long long)std::ceil((view0 + view_side - origin) / side) - 1;
    };
    long long x0, x1, y0, y1;
    span(repeat_x, s.offset_x, w, out.cull ? out.cull->x : 0, out.cull ? out.cull->width : 0, &x0, &x1);
    span(repeat_y, s.offset_y, h, out.cull ? out.cull->y : 0, out.cull ? out.cull->height : 0, &y0, &y1);
    if ((x1 - x0 + 1) * (y1 - y0 + 1) > kMaxElements)
        throw Error(where + ": the repeated image needs more than " + std::to_string(kMaxElements) + " elements (kMaxMapElements)");
    for (long long ky = y0; ky <= y1; ++ky)
        for (long long kx = x0; kx <= x1; ++kx) {
            Element e;
            e.image = index;
            e.rect = {0, 0, w, h};
            e.transform = {1, 0, 0, 1, s.offset_x + double(kx) * w, s.offset_y + double(ky) * h};
            e.color = element_color(s);
            push(out, e, where);
        }
}

} // namespace

Vec2 hex_cell_top_left(const MapInfo& m, int col, int row) {
    // Tiled rounds the tile size down to even so the half sizes are whole.
    const double tw = m.tile_width & ~1, th = m.tile_height & ~1;
    const double side_x = m.stagger_x ? m.hex_side : 0, side_y = m.stagger_x ? 0 : m.hex_side;
    const double column_width = (tw - side_x) / 2 + side_x, row_height = (th - side_y) / 2 + side_y;
    if (m.stagger_x) {
        bool staggered = ((col & 1) != 0) != m.stagger_even;
        return {double(col) * column_width, double(row) * (th + side_y) + (staggered ? row_height : 0)};
    }
    bool staggered = ((row & 1) != 0) != m.stagger_even;
    return {double(col) * (tw + side_x) + (staggered ? column_width : 0), double(row) * row_height};
}

Box element_bounds(const Element& e) {
    Vec2 corners[4] = {apply(e.transform, {0, 0}), apply(e.transform, {double(e.rect.w), 0}),
                       apply(e.transform, {0, double(e.rect.h)}), apply(e.transform, {double(e.rect.w), double(e.rect.h)})};
    Box b{corners[0].x, corners[0].y, corners[0].x, corners[0].y};
    for (const Vec2& p : corners) {
        b.x0 = std::min(b.x0, p.x);
        b.y0 = std::min(b.y0, p.y);
        b.x1 = std::max(b.x1, p.x);
        b.y1 = std::max(b.y1, p.y);
    }
    return b;
}

void emit_layers(pugi::xml_node parent, const LayerState& state, Emitter& out, int depth) {
    // 20,000 nested groups (646 bytes gzipped) overflowed the stack.
    if (depth > limits::kMaxNestingDepth)
        throw Error(out.info.where + ": groups nested deeper than " + std::to_string(limits::kMaxNestingDepth) + " (kMaxNestingDepth)");
    int count = 0;
    for (pugi::xml_node layer : parent.children()) {
        std::string kind = layer.name();
        if (kind != "layer" && kind != "objectgroup" && kind != "imagelayer" && kind != "group") continue;
        if (++count > kMaxLayers) throw Error(out.info.where + ": more than " + std::to_string(kMaxLayers) + " layers (kMaxLayers)");
        std::string where = out.info.where + ": " + (kind == "objectgroup" ? "object layer" : kind == "group" ? "group" : kind == "imagelayer" ? "image layer" : "layer") +
                            " '" + layer.attribute("name").as_string() + "'";
        // A layer named by LoadOptions::insert_at: moving sprites go after
        // its elements (also when it draws nothing: where it would be).
        const std::string name = layer.attribute("name").as_string();
        const bool named = out.options && std::find(out.options->insert_at.begin(), out.options->insert_at.end(), name) != out.options->insert_at.end();
        if (named) out.insert_at_found.insert(name);
        auto emit_layer = [&] {
            if (!visible_attr(layer, where)) return;
            LayerState s = child_state(layer, state, where);
            if (s.opacity == 0) return; // draws nothing
            // Tiled 1.11's layer blend modes: drawn as normal (alpha) blending.
            if (std::string mode = layer.attribute("mode").as_string("normal"); mode != "normal")
                warn(out, where + ": layer blend mode '" + mode + "' is drawn as normal");
            if (kind == "group") {
                emit_layers(layer, s, out, depth + 1);
                return;
            }
            if (s.parallax_x != 1 || s.parallax_y != 1) {
                // Tiled's MapScene::parallaxOffset: a layer moves by (1 - factor)
                // times the camera centre's distance from the parallax origin.
                if (!out.cull) {
                    warn(out, where + ": parallax factor ignored (an infinite map needs --viewport to place it)");
                } else {
                    double cx = out.cull->x + out.cull->width / 2.0, cy = out.cull->y + out.cull->height / 2.0;
                    s.offset_x += (1 - s.parallax_x) * (cx - out.info.parallax_origin_x);
                    s.offset_y += (1 - s.parallax_y) * (cy - out.info.parallax_origin_y);
                    char text[160];
                    std::snprintf(text, sizeof text, ": parallax layer placed for the camera centred at %g,%g: meshes are valid for this camera only",
                                  cx, cy);
                    note(out, where + text);
                }
            }
            if (kind == "layer") emit_tile_layer(layer, s, out, where);
            else if (kind == "objectgroup") {
                emit_object_group(layer, s, out, where);
                // The game layer: moving sprites are drawn over its objects (Scene::insertion_points).
                out.scene.insertion_points.push_back(out.scene.elements.size());
            }
            else emit_image_layer(layer, s, out, where);
        };
        emit_layer();
        if (named) out.scene.insertion_points.push_back(out.scene.elements.size());
    }
}

} // namespace depthcull::io::tiled
