// Tiled tilesets: inline and external (.tsx, also gzipped), image tilesets
// cut into tiles by tile size, margin and spacing, image-collection
// tilesets, animations (drawn at their first frame, as Tiled shows a map at
// time zero, and recorded as Scene::animations so every frame is analyzed
// and an engine can animate the meshes), and the trans colour key.
//
// The trans key: Tiled makes texels of the key colour transparent when it
// loads the image; the PNG on disk does not say so. The key travels on the
// SceneImage (has_trans, trans) and is applied where the file is decoded
// (io::read_scene_image): loading a map writes nothing.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "io/tiled_internal.h"

namespace fs = std::filesystem;

namespace depthcull::io::tiled {

namespace {

// Tiled resolves an image relative to the file naming it. Some games'
// maps name paths relative to their data root instead (btanks'
// four_rooms.tmx: "../../../data/tilesets/x.png"); when the Tiled path
// does not exist we try the path without its leading "../" against the
// file's directory and its ancestors, nearest first.
fs::path resolve_image(const std::string& base_dir, const std::string& source) {
    fs::path base = base_dir.empty() ? fs::path() : fs::path(base_dir);
    fs::path direct = (fs::path(source).is_absolute() ? fs::path(source) : base / source).lexically_normal();
    std::error_code ec;
    if (fs::exists(direct, ec) || fs::path(source).is_absolute()) return direct;
    fs::path rest;
    bool leading = true;
    for (const fs::path& part : fs::path(source)) {
        if (leading && (part == ".." || part == ".")) continue;
        leading = false;
        rest /= part;
    }
    fs::path dir = fs::absolute(base.empty() ? fs::path(".") : base, ec).lexically_normal();
    for (int up = 0; up < 8 && !dir.empty(); ++up) {
        fs::path candidate = dir / rest;
        if (fs::exists(candidate, ec)) return (base / fs::relative(candidate, fs::absolute(base.empty() ? "." : base, ec), ec)).lexically_normal();
        if (dir == dir.root_path()) break;
        dir = dir.parent_path();
    }
    return direct;
}

std::string dir_of(const std::string& path) { return fs::path(path).parent_path().string(); }

Alignment parse_alignment(const std::string& text, const std::string& where) {
    static const std::pair<const char*, Alignment> names[] = {
        {"unspecified", Alignment::unspecified}, {"topleft", Alignment::topleft}, {"top", Alignment::top},
        {"topright", Alignment::topright},       {"left", Alignment::left},       {"center", Alignment::center},
        {"right", Alignment::right},             {"bottomleft", Alignment::bottomleft}, {"bottom", Alignment::bottom},
        {"bottomright", Alignment::bottomright}};
    if (text.empty()) return Alignment::unspecified;
    for (const auto& [name, value] : names)
        if (text == name) return value;
    throw Error(where + ": unknown objectalignment '" + text + "'");
}

// An image tileset cut like Tiled's Tileset::sliceImage: tiles start at
// `margin` and are `spacing` apart; a partial tile at the right or bottom
// edge is not a tile. Margin and spacing beyond the image's side cut no
// tile, and bounding them keeps every tile's position within int.
void slice_image(Tileset& ts, int image, int image_w, int image_h, int margin, int spacing, const std::string& where) {
    if (ts.tile_width <= 0 || ts.tile_height <= 0 || ts.tile_width > kMaxImageSide || ts.tile_height > kMaxImageSide)
        throw Error(where + ": tile size must be 1.." + std::to_string(kMaxImageSide) + " (kMaxImageSide)");
    if (margin < 0 || spacing < 0 || margin > kMaxImageSide || spacing > kMaxImageSide)
        throw Error(where + ": margin and spacing must be 0.." + std::to_string(kMaxImageSide) + " (kMaxImageSide)");
    int columns = image_w - margin >= ts.tile_width ? (image_w - margin - ts.tile_width) / (ts.tile_width + spacing) + 1 : 0;
    int rows = image_h - margin >= ts.tile_height ? (image_h - margin - ts.tile_height) / (ts.tile_height + spacing) + 1 : 0;
    if (columns == 0 || rows == 0)
        throw Error(where + ": image " + std::to_string(image_w) + "x" + std::to_string(image_h) + " holds no " +
                    std::to_string(ts.tile_width) + "x" + std::to_string(ts.tile_height) + " tile");
    ts.image = image;
    ts.columns = columns;
    ts.rows = rows;
    ts.margin = margin;
    ts.spacing = spacing;
}

Tileset parse_tileset(pugi::xml_node node, std::uint32_t firstgid, const std::string& file, const std::string& where,
                      ImageTable& images) {
    Tileset ts;
    auto tables = std::make_shared<Tileset::Tables>();
    ts.tables = tables;
    ts.firstgid = firstgid;
    ts.name = node.attribute("name").as_string();
    ts.tile_width = int_attr(node, "tilewidth", 0, where);
    ts.tile_height = int_attr(node, "tileheight", 0, where);
    ts.alignment = parse_alignment(node.attribute("objectalignment").as_string(), where);
    std::string render_size = node.attribute("tilerendersize").as_string("tile");
    std::string fill = node.attribute("fillmode").as_string("stretch");
    if (render_size != "tile" && render_size != "grid") throw Error(where + ": unknown tilerendersize '" + render_size + "'");
    if (fill != "stretch" && fill != "preserve-aspect-fit")
        throw Error(where + ": fillmode '" + fill + "' is not supported (only stretch and preserve-aspect-fit)");
    ts.render_grid_size = render_size == "grid";
    ts.preserve_aspect = ts.render_grid_size && fill == "preserve-aspect-fit";
    if (pugi::xml_node offset = node.child("tileoffset")) {
        ts.offset_x = double_attr(offset, "x", 0, where);
        ts.offset_y = double_attr(offset, "y", 0, where);
        if (!(std::fabs(ts.offset_x) <= limits::kMaxCoordinate && std::fabs(ts.offset_y) <= limits::kMaxCoordinate))
            throw Error(where + ": tileoffset is not a finite number within +-1e9 (kMaxCoordinate)");
    }
    std::string base_dir = dir_of(file);
    auto add_image = [&](pugi::xml_node image, const std::string& here) {
        if (!image.attribute("source")) throw Error(here + ": embedded image data is not supported (save the image as a file)");
        return images.add(base_dir, image.attribute("source").as_string(), image.attribute("trans").as_string(), here);
    };
    if (pugi::xml_node image = node.child("image")) {
        int index = add_image(image, where);
        slice_image(ts, index, images.width(index), images.height(index), int_attr(node, "margin", 0, where),
                    int_attr(node, "spacing", 0, where), where);
    }
    for (pugi::xml_node tile : node.children("tile")) {
        std::string here = where + ": tile " + tile.attribute("id").as_string();
        int id = int_attr(tile, "id", -1, here);
        if (id < 0 || std::uint32_t(id) > kGidMask) throw Error(here + ": tile id out of range 0.." + std::to_string(kGidMask));
        pugi::xml_node image = tile.child("image");
        if (!image) continue;
        if (node.child("image")) throw Error(here + ": a tile image in a tileset that has one image");
        int index = add_image(image, here);
        Rect full{0, 0, images.width(index), images.height(index)};
        Rect rect{int_attr(tile, "x", 0, here), int_attr(tile, "y", 0, here), int_attr(tile, "width", full.w, here),
                  int_attr(tile, "height", full.h, here)};
        if (rect.empty() || rect.x < 0 || rect.y < 0 || rect.x > full.w - rect.w || rect.y > full.h - rect.h)
            throw Error(here + ": sub-rectangle lies outside its image");
        tables->named[std::uint32_t(id)] = {index, rect};
    }
    // Animations: the first frame is what Tiled shows at time zero (looked
    // up among the still tiles, before any animation is resolved).
    std::vector<std::pair<std::uint32_t, std::vector<std::pair<Tile, int>>>> animated;
    for (pugi::xml_node tile : node.children("tile")) {
        // The Mana World's own form (its client reads it; 11 of its
        // tilesets use it): not read here, so the tile is drawn still.
        if (!tile.child("animation") && tile.child("properties").find_child_by_attribute("property", "name", "animation-frame0"))
            tables->animation_warnings[std::uint32_t(int_attr(tile, "id", 0, where))] =
                "animation-frameN / animation-delayN properties (The Mana World's form) are not read: drawn as its still tile";
        if (!tile.child("animation").child("frame")) continue;
        std::string here = where + ": tile " + tile.attribute("id").as_string() + ": animation";
        int id = int_attr(tile, "id", -1, here);
        std::vector<std::pair<Tile, int>> frames;
        for (pugi::xml_node frame : tile.child("animation").children("frame")) {
            if (frames.size() >= limits::kMaxAnimationFrames)
                throw Error(here + ": more than " + std::to_string(limits::kMaxAnimationFrames) + " frames (kMaxAnimationFrames)");
            int tile_id = int_attr(frame, "tileid", -1, here);
            Tile still = tile_id < 0 ? Tile{} : ts.tile(std::uint32_t(tile_id));
            int duration = int_attr(frame, "duration", 0, here);
            if (duration < 0) throw Error(here + ": negative frame duration");
            // The Mana World's water tileset animates two tiles through ids
            // past its image, and nine of its maps (none showing those
            // tiles) load in Tiled and the game: refused only where shown.
            if (still.image < 0) {
                std::string& why = tables->animation_warnings[std::uint32_t(id)];
                why += (why.empty() ? "frame names no tile (" : ", ") + std::to_string(tile_id);
                continue;
            }
            frames.emplace_back(still, duration);
        }
        if (auto it = tables->animation_warnings.find(std::uint32_t(id)); it != tables->animation_warnings.end())
            it->second += "; the tileset has " + std::to_string(ts.tile_count()) + " tiles): those frames are left out";
        if (!frames.empty()) animated.emplace_back(std::uint32_t(id), std::move(frames));
    }
    for (auto& [id, frames] : animated) {
        tables->named[id] = frames.front().first;
        tables->animations[id] = std::move(frames);
    }
    return ts;
}

} // namespace

int ImageTable::add(const std::string& base_dir, const std::string& source, const std::string& trans, const std::string& where) {
    if (source.empty()) throw Error(where + ": image has no source");
    fs::path resolved = resolve_image(base_dir, source);
    std::error_code ec;
    if (!fs::is_regular_file(resolved, ec)) throw Error(where + ": image '" + source + "' not found (" + resolved.string() + ")");
    std::string path = resolved.string();
    std::string key = path + "\n" + (trans.empty() ? std::string() : color_key_text(parse_color_key(trans, where)));
    if (auto it = by_key_.find(key); it != by_key_.end()) return it->second;
    SceneImage image;
    if (!trans.empty()) {
        image.has_trans = true;
        image.trans = parse_color_key(trans, where);
    }
    image_size(path, &image.width, &image.height, files_);
    // Ids: the file stem, numbered when two files share a stem.
    std::string stem = resolved.stem().string();
    if (stem.empty()) stem = "image";
    image.id = stem;
    for (int n = 2; ids_.count(image.id); ++n) image.id = stem + "-" + std::to_string(n);
    ids_.insert(image.id);
    image.path = path;
    images_.push_back(std::move(image));
    int index = int(images_.size()) - 1;
    by_key_.emplace(key, index);
    return index;
}

int ImageTable::add_fill(std::uint32_t rgb) {
    std::string key = "\nfill " + color_key_text(rgb);
    if (auto it = by_key_.find(key); it != by_key_.end()) return it->second;
    SceneImage image;
    image.has_fill = true;
    image.fill = rgb;
    image.width = image.height = kFillImageSide;
    image.id = "background";
    for (int n = 2; ids_.count(image.id); ++n) image.id = "background-" + std::to_string(n);
    ids_.insert(image.id);
    images_.push_back(std::move(image));
    by_key_.emplace(key, int(images_.size()) - 1);
    return int(images_.size()) - 1;
}

std::string resolve_tsx(const std::string& base_dir, const std::string& source) {
    std::string tsx = (fs::path(base_dir) / source).lexically_normal().string();
    // Debian (dh_compress) gzips example tilesets but not the files naming them.
    std::error_code ec;
    if (!fs::exists(tsx, ec) && fs::exists(tsx + ".gz", ec)) tsx += ".gz";
    return tsx;
}

Tileset tileset_from_bytes(std::string_view bytes, const std::string& tsx, std::uint32_t firstgid, ImageTable& images) {
    std::string text = maybe_gunzip(bytes, tsx);
    pugi::xml_document doc;
    if (looks_like_json(text)) {
        json_tileset_to_xml(text, tsx, doc); // .tsj, or .json by content
    } else {
        check_xml_document(text, tsx);
        pugi::xml_parse_result ok = doc.load_buffer(text.data(), text.size());
        if (!ok) throw Error(tsx + ": XML error at byte " + std::to_string(ok.offset) + ": " + ok.description());
    }
    pugi::xml_node root = doc.child("tileset");
    if (!root) throw Error(tsx + ": no <tileset> element");
    std::string here = tsx + (root.attribute("name") ? ": tileset '" + std::string(root.attribute("name").as_string()) + "'" : "");
    Tileset ts = parse_tileset(root, firstgid, tsx, here, images);
    ts.source = tsx;
    return ts;
}

std::vector<Tileset> read_tilesets(pugi::xml_node map, const std::string& map_path, ImageTable& images) {
    std::vector<Tileset> tilesets;
    std::map<std::string, Tileset> external; // by file_identity: each file parsed once
    for (pugi::xml_node node : map.children("tileset")) {
        if (int(tilesets.size()) >= kMaxTilesets)
            throw Error(map_path + ": more than " + std::to_string(kMaxTilesets) + " tilesets (kMaxTilesets)");
        std::string where = map_path + ": tileset " + std::to_string(tilesets.size());
        if (node.attribute("name")) where = map_path + ": tileset '" + node.attribute("name").as_string() + "'";
        long long firstgid = llong_attr(node, "firstgid", 0, where);
        if (firstgid < 1 || firstgid > kGidMask) throw Error(where + ": firstgid missing or out of range");
        if (pugi::xml_attribute source = node.attribute("source")) {
            std::string tsx = resolve_tsx(dir_of(map_path), source.as_string());
            auto [it, fresh] = external.try_emplace(file_identity(tsx));
            if (fresh) it->second = tileset_from_bytes(read_file(tsx), tsx, 0, images);
            tilesets.push_back(it->second);
            tilesets.back().firstgid = std::uint32_t(firstgid);
        } else {
            tilesets.push_back(parse_tileset(node, std::uint32_t(firstgid), map_path, where, images));
        }
    }
    std::stable_sort(tilesets.begin(), tilesets.end(), [](const Tileset& a, const Tileset& b) { return a.firstgid < b.firstgid; });
    return tilesets;
}

std::uint32_t Tileset::tile_count() const {
    std::uint32_t grid = std::uint32_t(columns) * std::uint32_t(rows);
    return tables->named.empty() ? grid : std::max(grid, tables->named.rbegin()->first + 1);
}

Tile Tileset::tile(std::uint32_t local) const {
    if (auto it = tables->named.find(local); it != tables->named.end()) return it->second;
    if (image < 0 || local >= std::uint32_t(columns) * std::uint32_t(rows)) return {};
    const int c = int(local % std::uint32_t(columns)), r = int(local / std::uint32_t(columns));
    return {image, {margin + c * (tile_width + spacing), margin + r * (tile_height + spacing), tile_width, tile_height}};
}

TileRef find_tile(const std::vector<Tileset>& tilesets, std::uint32_t gid, const std::string& where) {
    auto it = std::upper_bound(tilesets.begin(), tilesets.end(), gid, [](std::uint32_t g, const Tileset& t) { return g < t.firstgid; });
    if (it == tilesets.begin()) throw Error(where + ": gid " + std::to_string(gid) + " has no tileset");
    const Tileset& ts = *(it - 1);
    const Tile tile = ts.tile(gid - ts.firstgid);
    if (tile.image < 0)
        throw Error(where + ": gid " + std::to_string(gid) + " is out of range of tileset '" + ts.name + "' (" +
                    std::to_string(ts.tile_count()) + " tiles from gid " + std::to_string(ts.firstgid) + ")");
    return {&ts, tile};
}

} // namespace depthcull::io::tiled
