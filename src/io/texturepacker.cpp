// TexturePacker JSON atlases, hash form {"frames": {"name": {...}}} and
// array form {"frames": [{"filename": "name", ...}]}, and the placement of
// a frame's texels so an element draws the untrimmed sprite.
//
// Conventions (TexturePacker's, as PixiJS and Phaser read them):
// - "frame" {x, y, w, h}: w and h are the trimmed sprite's size UNROTATED;
//   a rotated frame occupies h x w texels of the page at (x, y).
// - "rotated": the sprite is stored turned 90 degrees clockwise, so sprite
//   texel (u, v) (u < w, v < h) sits at page (x + h - v, y + u) (continuous
//   coordinates: the sprite's top-left corner is the stored top-right one).
// - "spriteSourceSize" {x, y}: where the trimmed sprite's top-left lies in
//   the untrimmed sprite of "sourceSize" {w, h}.
// - Multipack (Phaser 3's default): {"textures": [{"image", "size",
//   "frames": [...]}, ...]}, frames named uniquely across pages;
//   "meta.related_multi_packs" needs nothing: each page's JSON stands alone.
// - spriteSourceSize w/h differing from the frame's (Aseprite, some Flash
//   exporters): the frame's size is the trimmed sprite's, as Phaser and
//   PixiJS read it.
// cocos2d-x plists are read in cocos2d_plist.cpp.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "depthcull/io.h"
#include "depthcull/limits.h"
#include "io/formats.h"
#include "io/json_keys.h"

namespace depthcull::io {

namespace {

// Plain (std::map) objects: ordered_json finds keys linearly, so a
// 200,000-frame hash took 30 s to parse. The hash form's file order ("in
// file order" holds for it too) is recorded while parsing instead.
using Json = nlohmann::json;
constexpr std::size_t kMaxFrames = limits::kMaxAtlasFrames;

int int_field(const Json& obj, const char* key, const std::string& where, int min, int max, bool required = true,
              int fallback = 0) {
    auto it = obj.find(key);
    if (it == obj.end()) {
        if (required) throw Error(where + ": missing \"" + key + "\"");
        return fallback;
    }
    // TexturePacker writes integers; accept integral floats ("12.0") too.
    double v = it->is_number() ? it->get<double>() : 0.5;
    if (!std::isfinite(v) || v != std::floor(v)) throw Error(where + ": \"" + key + "\" is not an integer");
    if (v < min || v > max) {
        char text[32];
        std::snprintf(text, sizeof text, "%.15g", v);
        throw Error(where + ": \"" + key + "\" = " + text + " is outside " + std::to_string(min) + ".." + std::to_string(max));
    }
    return int(v);
}

const Json& object_field(const Json& obj, const char* key, const std::string& where) {
    auto it = obj.find(key);
    if (it == obj.end() || !it->is_object()) throw Error(where + ": missing object \"" + key + "\"");
    return *it;
}

bool bool_field(const Json& obj, const char* key, const std::string& where) {
    auto it = obj.find(key);
    if (it == obj.end() || it->is_null()) return false;
    if (it->is_boolean()) return it->get<bool>();
    if (it->is_number_integer()) return it->get<std::int64_t>() != 0;
    throw Error(where + ": \"" + key + "\" is not a boolean");
}

// meta.scale as PixiJS reads it: parseFloat of a string ("0.5"), a number
// as it is, 1 when absent; 0 when it reads as no positive number.
double meta_scale(const Json& meta) {
    auto it = meta.find("scale");
    if (it == meta.end() || it->is_null()) return 1;
    double v = 0;
    if (it->is_number()) v = it->get<double>();
    else if (it->is_string()) v = std::strtod(it->get_ref<const std::string&>().c_str(), nullptr);
    return std::isfinite(v) && v > 0 ? v : 0;
}

AtlasFrame read_frame(const std::string& name, const Json& f, const std::string& where, std::vector<std::string>* warnings) {
    if (!f.is_object()) throw Error(where + ": frame is not an object");
    AtlasFrame frame;
    frame.name = name;
    const Json& r = object_field(f, "frame", where);
    int x = int_field(r, "x", where + ": frame", 0, kMaxImageSide);
    int y = int_field(r, "y", where + ": frame", 0, kMaxImageSide);
    int w = int_field(r, "w", where + ": frame", 1, kMaxImageSide);
    int h = int_field(r, "h", where + ": frame", 1, kMaxImageSide);
    frame.rotated = bool_field(f, "rotated", where);
    frame.trimmed = bool_field(f, "trimmed", where);
    frame.frame = frame.rotated ? Rect{x, y, h, w} : Rect{x, y, w, h};
    frame.sprite_source = {0, 0, w, h};
    if (auto it = f.find("spriteSourceSize"); it != f.end()) {
        const std::string here = where + ": spriteSourceSize";
        if (!it->is_object()) throw Error(here + " is not an object");
        frame.sprite_source.x = int_field(*it, "x", here, -kMaxImageSide, kMaxImageSide);
        frame.sprite_source.y = int_field(*it, "y", here, -kMaxImageSide, kMaxImageSide);
        // Its w / h are checked as numbers but not used: engines take the
        // trimmed size from "frame".
        (void)int_field(*it, "w", here, 0, kMaxImageSide, false, w);
        (void)int_field(*it, "h", here, 0, kMaxImageSide, false, h);
    }
    frame.source_w = w;
    frame.source_h = h;
    if (auto it = f.find("sourceSize"); it != f.end()) {
        const std::string here = where + ": sourceSize";
        if (!it->is_object()) throw Error(here + " is not an object");
        frame.source_w = int_field(*it, "w", here, 1, kMaxImageSide);
        frame.source_h = int_field(*it, "h", here, 1, kMaxImageSide);
    }
    // Aseprite trims a sprite one texel past its sourceSize at times;
    // PixiJS and Phaser draw it where spriteSourceSize puts it, and so do we.
    const Rect& s = frame.sprite_source;
    if (s.x < 0 || s.y < 0 || s.x + s.w > frame.source_w || s.y + s.h > frame.source_h)
        warnings->push_back(where + ": trimmed sprite at " + std::to_string(s.x) + "," + std::to_string(s.y) + " size " +
                            std::to_string(s.w) + "x" + std::to_string(s.h) + " reaches outside sourceSize " +
                            std::to_string(frame.source_w) + "x" + std::to_string(frame.source_h) +
                            "; drawn where spriteSourceSize puts it, as PixiJS and Phaser draw it");
    return frame;
}

} // namespace

const AtlasFrame* Atlas::find(const std::string& name) const {
    // The index when it describes `frames` (read_atlas fills it):
    // 20,000 elements naming frames of a 200,000-frame atlas took 45 s by
    // the linear search below.
    if (by_name.size() == frames.size()) {
        auto it = by_name.find(name);
        return it != by_name.end() && it->second < frames.size() && frames[it->second].name == name ? &frames[it->second] : nullptr;
    }
    for (const AtlasFrame& f : frames)
        if (f.name == name) return &f;
    return nullptr;
}

namespace {

// The document, and in *frame_order the hash form's frame names in file order.
Json parse_json_text(std::string_view text, const std::string& path, std::vector<std::string>* frame_order) {
    check_json_depth(text, path);
    // The keys of a top-level "frames" object in file order (duplicates
    // included). Not a parse callback: nlohmann then scans the parent
    // object at every member's end, quadratic in the frame count.
    bool in_frames = false;
    try {
        scan_json_keys(text, [&](int depth, std::string_view key) {
            if (depth == 1) in_frames = key == "frames";
            else if (depth == 2 && in_frames) frame_order->emplace_back(key);
            return true;
        });
        return Json::parse(text);
    } catch (const Json::exception& e) { // parse_error, and out_of_range for numbers like 1e400
        throw_json_error(e, text, path);
    }
}

} // namespace

namespace {

Atlas read_multipack(const std::string& path, const Json& doc);

Atlas parse_texturepacker(std::string_view text, const std::string& path) {
    // A cocos2d-x .plist (XML) rather than TexturePacker JSON.
    if (std::size_t first = text.substr(0, 256).find_first_not_of(" \t\r\n"); first != std::string_view::npos && text[first] == '<')
        return load_cocos2d_plist(path);
    std::vector<std::string> order;
    Json doc = parse_json_text(text, path, &order);
    if (!doc.is_object()) throw Error(path + ": not a TexturePacker atlas (top level is not an object)");
    if (doc.contains("textures") && !doc.contains("frames")) return read_multipack(path, doc);
    auto frames = doc.find("frames");
    if (frames == doc.end() || !(frames->is_object() || frames->is_array()))
        throw Error(path + ": not a TexturePacker atlas (no \"frames\" object or array)");
    if (frames->size() > kMaxFrames) throw Error(path + ": more than " + std::to_string(kMaxFrames) + " frames");

    Atlas atlas;
    atlas.path = path;
    const Json meta = doc.contains("meta") && doc["meta"].is_object() ? doc["meta"] : Json::object();
    auto image = meta.find("image");
    if (image == meta.end() || !image->is_string() || image->get<std::string>().empty())
        throw Error(path + ": meta.image (the atlas page) is missing");
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    atlas.image_path = (dir / image->get<std::string>()).lexically_normal().string();
    if (auto size = meta.find("size"); size != meta.end() && size->is_object()) {
        atlas.width = int_field(*size, "w", path + ": meta.size", 1, kMaxImageSide);
        atlas.height = int_field(*size, "h", path + ": meta.size", 1, kMaxImageSide);
    }
    atlas.pages.push_back({atlas.image_path, atlas.width, atlas.height});
    atlas.form = frames->is_object() ? AtlasForm::json_hash : AtlasForm::json_array;
    atlas.scale = meta_scale(meta);

    // Frames are checked against the decoded page (check_atlas_pages), not
    // meta.size: a page re-saved smaller still loads in PixiJS and Phaser.
    auto add = [&](const std::string& name, const Json& f) {
        std::string where = path + ": frame '" + name + "'";
        if (!atlas.by_name.emplace(name, atlas.frames.size()).second) throw Error(where + ": duplicate frame name");
        atlas.frames.push_back(read_frame(name, f, where, &atlas.warnings));
    };
    if (frames->is_object()) {
        // A name given twice is refused by add(), as the parsed object kept one.
        for (const std::string& name : order) add(name, frames->at(name));
    } else {
        std::size_t index = 0;
        for (const Json& f : *frames) {
            auto name = f.is_object() ? f.find("filename") : f.end();
            if (name == f.end() || !name->is_string())
                throw Error(path + ": frame " + std::to_string(index) + ": missing \"filename\"");
            add(name->get<std::string>(), f);
            ++index;
        }
    }
    return atlas;
}

Atlas read_multipack(const std::string& path, const Json& doc) {
    const Json& textures = doc["textures"];
    if (!textures.is_array() || textures.empty()) throw Error(path + ": \"textures\" must be a non-empty array of pages");
    Atlas atlas;
    atlas.path = path;
    atlas.form = AtlasForm::json_multipack;
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    std::size_t total = 0;
    for (std::size_t k = 0; k < textures.size(); ++k) {
        const std::string where = path + ": textures[" + std::to_string(k) + "]";
        const Json& t = textures[k];
        if (!t.is_object()) throw Error(where + " is not an object");
        auto image = t.find("image");
        if (image == t.end() || !image->is_string() || image->get<std::string>().empty()) throw Error(where + ": \"image\" is missing");
        AtlasPage page{(dir / image->get<std::string>()).lexically_normal().string(), 0, 0};
        if (auto size = t.find("size"); size != t.end() && size->is_object()) {
            page.width = int_field(*size, "w", where + ": size", 1, kMaxImageSide);
            page.height = int_field(*size, "h", where + ": size", 1, kMaxImageSide);
        }
        auto frames = t.find("frames");
        if (frames == t.end() || !frames->is_array()) throw Error(where + ": \"frames\" must be an array");
        total += frames->size();
        if (total > kMaxFrames) throw Error(path + ": more than " + std::to_string(kMaxFrames) + " frames");
        for (std::size_t i = 0; i < frames->size(); ++i) {
            const Json& f = (*frames)[i];
            auto name = f.is_object() ? f.find("filename") : f.end();
            if (name == f.end() || !name->is_string()) throw Error(where + ": frame " + std::to_string(i) + ": missing \"filename\"");
            std::string here = path + ": frame '" + name->get<std::string>() + "'";
            if (!atlas.by_name.emplace(name->get<std::string>(), atlas.frames.size()).second) throw Error(here + ": duplicate frame name");
            AtlasFrame frame = read_frame(name->get<std::string>(), f, here, &atlas.warnings);
            frame.page = int(k);
            atlas.frames.push_back(std::move(frame));
        }
        atlas.pages.push_back(std::move(page));
    }
    atlas.image_path = atlas.pages[0].image_path;
    atlas.width = atlas.pages[0].width;
    atlas.height = atlas.pages[0].height;
    const Json meta = doc.contains("meta") && doc["meta"].is_object() ? doc["meta"] : Json::object();
    atlas.scale = meta_scale(meta);
    return atlas;
}

} // namespace

Atlas read_atlas(const std::string& path) {
    return guarded(path, [&] {
        auto text = std::make_shared<const std::string>(read_file(path));
        Atlas atlas = parse_texturepacker(*text, path);
        if (atlas.form != AtlasForm::cocos2d_plist) atlas.text = std::move(text);
        return atlas;
    });
}

Atlas texturepacker_from_text(std::string_view text, const std::string& path) {
    return guarded(path, [&] { return parse_texturepacker(text, path); });
}

void check_atlas_pages(Atlas& atlas, const std::vector<std::array<int, 2>>& sizes) {
    auto size_text = [](int w, int h) { return std::to_string(w) + "x" + std::to_string(h); };
    for (std::size_t k = 0; k < atlas.pages.size() && k < sizes.size(); ++k) {
        const AtlasPage& page = atlas.pages[k];
        if (page.width > 0 && (page.width != sizes[k][0] || page.height != sizes[k][1]))
            atlas.warnings.push_back(atlas.path + ": page " + page.image_path + " is " + size_text(sizes[k][0], sizes[k][1]) +
                                     ", the atlas states " + size_text(page.width, page.height) +
                                     "; frames read as texels of the image, as PixiJS and Phaser read them");
    }
    for (const AtlasFrame& frame : atlas.frames) {
        const std::size_t k = std::size_t(frame.page);
        if (k >= sizes.size()) continue;
        const Rect& r = frame.frame;
        if (std::int64_t(r.x) + r.w > sizes[k][0] || std::int64_t(r.y) + r.h > sizes[k][1])
            throw Error(atlas.path + ": frame '" + frame.name + "': texels " + std::to_string(r.x) + "," + std::to_string(r.y) + " " +
                        size_text(r.w, r.h) + " lie outside the " + size_text(sizes[k][0], sizes[k][1]) + " page " +
                        atlas.pages[k].image_path);
    }
}

FramePlacement place_frame(const AtlasFrame& frame, const std::array<double, 6>& t) {
    // local: element texel (s, t) of the stored rect -> untrimmed sprite.
    std::array<double, 6> local;
    const double sx = frame.sprite_source.x, sy = frame.sprite_source.y;
    if (frame.rotated) {
        // Inverse of the clockwise storage turn: sprite (u, v) = (t, h - s)
        // with h the sprite's height = the stored rect's width.
        local = {0, -1, 1, 0, sx, sy + double(frame.frame.w)};
    } else {
        local = {1, 0, 0, 1, sx, sy};
    }
    FramePlacement p;
    p.rect = frame.frame;
    p.transform = {t[0] * local[0] + t[2] * local[1],        t[1] * local[0] + t[3] * local[1],
                   t[0] * local[2] + t[2] * local[3],        t[1] * local[2] + t[3] * local[3],
                   t[0] * local[4] + t[2] * local[5] + t[4], t[1] * local[4] + t[3] * local[5] + t[5]};
    return p;
}

} // namespace depthcull::io
