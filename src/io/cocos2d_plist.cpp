// cocos2d-x sprite frames: the Apple property list SpriteFrameCache reads,
// formats 2 and 3 (what TexturePacker and free-tex-packer write).
//   format 2: "frame" {{x,y},{w,h}}, "offset" {x,y}, "rotated",
//             "sourceColorRect" {{x,y},{w,h}}, "sourceSize" {w,h}
//   format 3: "textureRect" {{x,y},{w,h}}, "spriteOffset", "spriteSize",
//             "spriteSourceSize" {w,h}, "textureRotated"
// Sizes are the sprite's unrotated, as in TexturePacker JSON; a rotated
// frame is stored turned 90 degrees clockwise (cocos2d-x's
// Sprite::setTextureCoords). "offset" is the trimmed sprite's centre minus
// the untrimmed one's, y up.
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <pugixml.hpp>

#include "depthcull/io.h"
#include "depthcull/limits.h"
#include "io/formats.h"

namespace depthcull::io {

namespace {

// The value node of `key` in a plist <dict>, or an empty node.
pugi::xml_node dict_value(pugi::xml_node dict, const char* key) {
    for (pugi::xml_node k = dict.child("key"); k; k = k.next_sibling("key"))
        if (std::string_view(k.text().get()) == key) return k.next_sibling();
    return {};
}

// "{a,b}" or "{{a,b},{c,d}}": the numbers, in order.
std::vector<double> numbers_of(pugi::xml_node value, std::size_t expect, const std::string& where) {
    if (std::string_view(value.name()) != "string") throw Error(where + ": expected a <string> like {x,y}");
    std::string text = value.text().get();
    std::vector<double> out;
    const char* p = text.c_str();
    while (*p) {
        if (*p == '{' || *p == '}' || *p == ',' || *p == ' ') {
            ++p;
            continue;
        }
        char* end = nullptr;
        double v = std::strtod(p, &end);
        if (end == p || !(std::fabs(v) <= limits::kMaxCoordinate)) throw Error(where + ": '" + text + "' is not a list of numbers");
        out.push_back(v);
        p = end;
    }
    if (out.size() != expect) throw Error(where + ": '" + text + "' has " + std::to_string(out.size()) + " numbers, expected " + std::to_string(expect));
    return out;
}

int whole(double v, int min, const std::string& where) {
    if (v != std::floor(v) || v < min || v > kMaxImageSide)
        throw Error(where + ": " + std::to_string(v) + " is not a whole number in " + std::to_string(min) + ".." + std::to_string(kMaxImageSide));
    return int(v);
}

bool boolean_of(pugi::xml_node value) { return std::string_view(value.name()) == "true"; }

} // namespace

Atlas load_cocos2d_plist(const std::string& path) {
    std::string text = read_file(path);
    check_xml_document(text, path);
    pugi::xml_document doc;
    pugi::xml_parse_result ok = doc.load_buffer(text.data(), text.size());
    if (!ok) throw Error(path + ": XML error at byte " + std::to_string(ok.offset) + ": " + ok.description());
    pugi::xml_node root = doc.child("plist").child("dict");
    if (!root) throw Error(path + ": not a cocos2d plist (no <plist><dict>)");
    pugi::xml_node frames = dict_value(root, "frames"), meta = dict_value(root, "metadata");
    if (std::string_view(frames.name()) != "dict") throw Error(path + ": not a cocos2d plist (no \"frames\" dict)");
    if (std::string_view(meta.name()) != "dict") throw Error(path + ": \"metadata\" dict is missing");
    Atlas atlas;
    atlas.path = path;
    atlas.form = AtlasForm::cocos2d_plist;
    atlas.plist_format = dict_value(meta, "format").text().as_int(-1);
    if (atlas.plist_format != 2 && atlas.plist_format != 3)
        throw Error(path + ": cocos2d plist format " + std::to_string(atlas.plist_format) + " is not supported (formats 2 and 3 are)");
    pugi::xml_node image = dict_value(meta, "realTextureFileName");
    if (!image || !*image.text().get()) image = dict_value(meta, "textureFileName");
    if (!image || !*image.text().get()) throw Error(path + ": metadata.textureFileName (the atlas page) is missing");
    atlas.image_path = (std::filesystem::path(path).parent_path() / image.text().get()).lexically_normal().string();
    if (pugi::xml_node size = dict_value(meta, "size")) {
        auto v = numbers_of(size, 2, path + ": metadata.size");
        atlas.width = whole(v[0], 1, path + ": metadata.size");
        atlas.height = whole(v[1], 1, path + ": metadata.size");
    }
    atlas.pages.push_back({atlas.image_path, atlas.width, atlas.height});
    for (pugi::xml_node k = frames.child("key"); k; k = k.next_sibling("key")) {
        std::string name = k.text().get();
        std::string where = path + ": frame '" + name + "'";
        pugi::xml_node f = k.next_sibling();
        if (std::string_view(f.name()) != "dict") throw Error(where + ": not a <dict>");
        if (atlas.frames.size() >= std::size_t(limits::kMaxAtlasFrames))
            throw Error(path + ": more than " + std::to_string(limits::kMaxAtlasFrames) + " frames");
        bool v3 = atlas.plist_format == 3;
        auto need = [&](const char* key) {
            pugi::xml_node v = dict_value(f, key);
            if (!v) throw Error(where + ": missing \"" + key + "\"");
            return v;
        };
        auto rect = numbers_of(need(v3 ? "textureRect" : "frame"), 4, where + (v3 ? ": textureRect" : ": frame"));
        auto source = numbers_of(need(v3 ? "spriteSourceSize" : "sourceSize"), 2, where + ": source size");
        AtlasFrame frame;
        frame.name = name;
        frame.rotated = boolean_of(dict_value(f, v3 ? "textureRotated" : "rotated"));
        int x = whole(rect[0], 0, where), y = whole(rect[1], 0, where), w = whole(rect[2], 1, where), h = whole(rect[3], 1, where);
        if (v3) {
            if (pugi::xml_node size = dict_value(f, "spriteSize")) {
                auto s = numbers_of(size, 2, where + ": spriteSize");
                w = whole(s[0], 1, where);
                h = whole(s[1], 1, where);
            }
        }
        frame.frame = frame.rotated ? Rect{x, y, h, w} : Rect{x, y, w, h};
        frame.source_w = whole(source[0], 1, where + ": source size");
        frame.source_h = whole(source[1], 1, where + ": source size");
        if (pugi::xml_node color_rect = v3 ? pugi::xml_node() : dict_value(f, "sourceColorRect")) {
            auto c = numbers_of(color_rect, 4, where + ": sourceColorRect");
            frame.sprite_source = {whole(c[0], 0, where), whole(c[1], 0, where), w, h};
        } else {
            pugi::xml_node offset_node = dict_value(f, v3 ? "spriteOffset" : "offset");
            auto o = offset_node ? numbers_of(offset_node, 2, where + ": offset") : std::vector<double>{0, 0};
            // centre offset (y up) -> top-left of the trimmed sprite (y down)
            double sx = (frame.source_w - w) / 2.0 + o[0], sy = (frame.source_h - h) / 2.0 - o[1];
            frame.sprite_source = {int(std::lround(sx)), int(std::lround(sy)), w, h};
            if (std::fabs(sx - std::round(sx)) > 1e-6 || std::fabs(sy - std::round(sy)) > 1e-6)
                throw Error(where + ": offset puts the trimmed sprite off the texel grid");
        }
        frame.trimmed = w != frame.source_w || h != frame.source_h;
        // As in TexturePacker JSON (texturepacker.cpp): a trimmed sprite
        // past its source size is drawn where it lies, with a warning; the
        // frame's texels are checked against the decoded page
        // (check_atlas_pages), not metadata.size.
        const Rect& s = frame.sprite_source;
        if (s.x < 0 || s.y < 0 || s.x + s.w > frame.source_w || s.y + s.h > frame.source_h)
            atlas.warnings.push_back(where + ": trimmed sprite at " + std::to_string(s.x) + "," + std::to_string(s.y) + " size " +
                                     std::to_string(s.w) + "x" + std::to_string(s.h) + " reaches outside its source size " +
                                     std::to_string(frame.source_w) + "x" + std::to_string(frame.source_h) +
                                     "; drawn where the plist puts it, as cocos2d-x draws it");
        if (!atlas.by_name.emplace(name, atlas.frames.size()).second) throw Error(where + ": duplicate frame name");
        atlas.frames.push_back(std::move(frame));
    }
    return atlas;
}

} // namespace depthcull::io
