// Tiled maps (.tmx, .tmx.gz) as scenes: one SceneImage per tileset image
// (or image-collection tile image), one Element per visible tile or tile
// object, in Tiled's drawing order. See tiled_layers.cpp for placement and
// order, tiled_tilesets.cpp for images, tiled_data.cpp for encodings.
//
// Orientations: orthogonal, isometric, staggered and hexagonal (both
// stagger axes and indices; hexagonal maps' 60 / 120-degree tile turns).
//
// Viewport: --viewport when given; otherwise the whole map (orthogonal:
// width*tilewidth x height*tileheight; isometric: the diamond's bounding
// box; staggered / hexagonal: Tiled's map bounding rect; infinite maps:
// the bounding box of what they draw), capped at
// kDefaultViewportMax per side from the map's top-left: pass --viewport to
// see the rest of a larger map. Elements that miss the viewport are dropped,
// so a camera rectangle over a huge map gives a small scene.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "io/formats.h"
#include "io/tiled_internal.h"

namespace depthcull::io {

namespace {

constexpr int kDefaultViewportMax = 4096;
constexpr int kMaxMapSide = limits::kMaxMapSide;

int positive_attr(pugi::xml_node node, const char* name, const std::string& where, int max) {
    long long v = tiled::llong_attr(node, name, 0, where);
    if (v <= 0 || v > max)
        throw Error(where + ": map attribute " + name + " missing or outside 1.." + std::to_string(max));
    return int(v);
}

tiled::MapInfo read_map_info(pugi::xml_node map, const std::string& path) {
    tiled::MapInfo info;
    info.where = path;
    std::string orientation = map.attribute("orientation").as_string("orthogonal");
    if (orientation == "orthogonal") info.orientation = tiled::Orientation::orthogonal;
    else if (orientation == "isometric") info.orientation = tiled::Orientation::isometric;
    else if (orientation == "staggered" || orientation == "hexagonal") info.orientation = tiled::Orientation::hexagonal;
    else throw Error(path + ": " + orientation + " maps are not supported (only orthogonal, isometric, staggered and hexagonal)");
    if (info.orientation == tiled::Orientation::hexagonal) {
        std::string axis = map.attribute("staggeraxis").as_string("y");
        std::string index = map.attribute("staggerindex").as_string("odd");
        if ((axis != "x" && axis != "y") || (index != "odd" && index != "even"))
            throw Error(path + ": unknown staggeraxis '" + axis + "' or staggerindex '" + index + "'");
        info.stagger_x = axis == "x";
        info.stagger_even = index == "even";
        info.hex_side = orientation == "hexagonal" ? tiled::int_attr(map, "hexsidelength", 0, path) : 0;
        info.hex_rotation = orientation == "hexagonal";
        if (info.hex_side < 0 || info.hex_side > kMaxImageSide) throw Error(path + ": hexsidelength out of range");
    }
    std::string order = map.attribute("renderorder").as_string("right-down");
    if (order == "right-down") info.render_order = tiled::RenderOrder::right_down;
    else if (order == "right-up") info.render_order = tiled::RenderOrder::right_up;
    else if (order == "left-down") info.render_order = tiled::RenderOrder::left_down;
    else if (order == "left-up") info.render_order = tiled::RenderOrder::left_up;
    else throw Error(path + ": unknown renderorder '" + order + "'");
    info.infinite = map.attribute("infinite").as_int(0) != 0;
    info.parallax_origin_x = tiled::double_attr(map, "parallaxoriginx", 0, path);
    info.parallax_origin_y = tiled::double_attr(map, "parallaxoriginy", 0, path);
    if (!(std::fabs(info.parallax_origin_x) <= limits::kMaxCoordinate && std::fabs(info.parallax_origin_y) <= limits::kMaxCoordinate))
        throw Error(path + ": parallaxoriginx / parallaxoriginy is not a finite number within +-1e9 (kMaxCoordinate)");
    info.tile_width = positive_attr(map, "tilewidth", path, kMaxImageSide);
    info.tile_height = positive_attr(map, "tileheight", path, kMaxImageSide);
    if (info.infinite) {
        info.width = std::max(0, tiled::int_attr(map, "width", 0, path));
        info.height = std::max(0, tiled::int_attr(map, "height", 0, path));
    } else {
        info.width = positive_attr(map, "width", path, kMaxMapSide);
        info.height = positive_attr(map, "height", path, kMaxMapSide);
    }
    return info;
}

// The whole map's screen rectangle, capped, or nullopt for infinite maps
// (their extent is what they draw).
bool default_viewport(const tiled::MapInfo& info, Viewport* v) {
    if (info.infinite) return false;
    double w, h;
    if (info.orientation == tiled::Orientation::orthogonal) {
        w = double(info.width) * info.tile_width;
        h = double(info.height) * info.tile_height;
    } else if (info.orientation == tiled::Orientation::isometric) {
        w = double(info.width + info.height) * info.tile_width / 2;
        h = double(info.width + info.height) * info.tile_height / 2;
    } else {
        // Tiled's HexagonalRenderer::mapBoundingRect: the last cell's far
        // corner, plus the stagger of the other axis' shifted cells.
        Vec2 last = tiled::hex_cell_top_left(info, info.width - 1, info.height - 1);
        Vec2 shifted = tiled::hex_cell_top_left(info, info.stagger_x ? 1 : 0, info.stagger_x ? 0 : 1);
        Vec2 plain = tiled::hex_cell_top_left(info, 0, 0);
        double tw = info.tile_width & ~1, th = info.tile_height & ~1;
        if (info.stagger_x) {
            double row_shift = std::abs(shifted.y - plain.y);
            w = last.x + tw;
            h = double(info.height) * th + (info.width > 1 ? row_shift : 0);
        } else {
            double column_shift = std::abs(shifted.x - plain.x);
            w = double(info.width) * tw + (info.height > 1 ? column_shift : 0);
            h = last.y + th;
        }
    }
    // At least 1 texel a side: hexagonal maps round the tile size down to
    // even, so 1-texel-high tiles make a 0-high map (a viewport no scene
    // may have).
    auto side = [](double extent) { return int(std::clamp(extent, 1.0, double(kDefaultViewportMax))); };
    *v = {0, 0, side(w), side(h)};
    return true;
}

Viewport drawn_extent(const Scene& scene) {
    if (scene.elements.empty()) return {0, 0, 1, 1};
    Box all = tiled::element_bounds(scene.elements.front());
    for (const Element& e : scene.elements) {
        Box b = tiled::element_bounds(e);
        all = {std::min(all.x0, b.x0), std::min(all.y0, b.y0), std::max(all.x1, b.x1), std::max(all.y1, b.y1)};
    }
    double x0 = std::floor(all.x0), y0 = std::floor(all.y0);
    auto side = [](double extent) { return int(std::clamp(std::ceil(extent), 1.0, double(kDefaultViewportMax))); };
    return {x0, y0, side(all.x1 - x0), side(all.y1 - y0)};
}

} // namespace

Scene tiled_map_from_bytes(std::string_view bytes, const std::string& path, const LoadOptions& options) {
    std::string text = tiled::maybe_gunzip(bytes, path);
    if (text.size() > tiled::kMaxXmlBytes) throw Error(path + ": map is larger than 256 MiB (kMaxXmlBytes)");
    // The parsed map stays while its templates are read: they are bounded
    // together (limits::kMaxDocumentBytes).
    const bool json = tiled::looks_like_json(text);
    const std::uint64_t held = json ? json_document_bytes(text, path) : xml_document_bytes(text);
    if (held > limits::kMaxDocumentBytes) json ? check_json_document(text, path) : check_xml_document(text, path);
    pugi::xml_document doc;
    if (json) {
        tiled::json_map_to_xml(text, path, doc);
    } else {
        pugi::xml_parse_result ok = doc.load_buffer(text.data(), text.size());
        if (!ok) throw Error(path + ": XML error at byte " + std::to_string(ok.offset) + ": " + ok.description());
    }
    pugi::xml_node map = doc.child("map");
    if (!map) throw Error(path + ": no <map> element (not a Tiled map)");
    tiled::MapInfo info = read_map_info(map, path);

    Scene scene;
    scene.filter = Filter::nearest;
    tiled::ImageTable images(scene.images, options.image_files);
    std::vector<tiled::Tileset> tilesets = tiled::read_tilesets(map, path, images);
    if (options.documents)
        for (const tiled::Tileset& ts : tilesets)
            if (!ts.source.empty()) options.documents->push_back(ts.source);

    Viewport viewport;
    bool known = true;
    if (options.has_viewport) viewport = options.viewport;
    else known = default_viewport(info, &viewport);
    tiled::Emitter out{info, tilesets, images, known ? &viewport : nullptr, scene};
    out.options = &options;
    out.documents = held;
    tiled::emit_layers(map, tiled::LayerState{}, out);
    for (const std::string& name : options.insert_at)
        if (!out.insert_at_found.count(name)) throw Error(path + ": --insert-at '" + name + "': the map has no layer of that name");
    scene.viewport = known ? viewport : drawn_extent(scene);
    if (!known) {
        const Viewport& v = scene.viewport;
        // Insertion points follow their elements: each becomes the count
        // of elements kept before it.
        std::vector<std::size_t> kept_before(scene.elements.size() + 1, 0);
        for (std::size_t i = 0; i < scene.elements.size(); ++i) {
            const Box b = tiled::element_bounds(scene.elements[i]);
            const bool outside = b.x1 <= v.x || b.y1 <= v.y || b.x0 >= v.x + v.width || b.y0 >= v.y + v.height;
            kept_before[i + 1] = kept_before[i] + (outside ? 0 : 1);
        }
        for (std::size_t& p : scene.insertion_points) p = kept_before[p];
        std::erase_if(scene.elements, [&](const Element& e) {
            Box b = tiled::element_bounds(e);
            return b.x1 <= v.x || b.y1 <= v.y || b.x0 >= v.x + v.width || b.y0 >= v.y + v.height;
        });
    }
    // The map's background colour: what Tiled clears to, drawn first as an
    // opaque element covering the camera (its alpha, when not 255, is the
    // element's colour alpha).
    if (pugi::xml_attribute bg = map.attribute("backgroundcolor"); bg && *bg.as_string()) {
        auto c = tiled::parse_color(bg.as_string(), path + ": backgroundcolor");
        auto byte = [](double v) { return std::uint32_t(std::lround(v * 255)); };
        int index = images.add_fill(byte(c[0]) << 16 | byte(c[1]) << 8 | byte(c[2]));
        Element e;
        e.image = index;
        e.rect = {0, 0, kFillImageSide, kFillImageSide};
        const Viewport& v = scene.viewport;
        e.transform = {double(v.width) / kFillImageSide, 0, 0, double(v.height) / kFillImageSide, v.x, v.y};
        e.color = {1, 1, 1, float(c[3])};
        if (c[3] > 0) {
            scene.elements.insert(scene.elements.begin(), e);
            for (std::size_t& p : scene.insertion_points) ++p; // the background is behind every layer
        }
    }
    std::sort(scene.insertion_points.begin(), scene.insertion_points.end());
    scene.insertion_points.erase(std::unique(scene.insertion_points.begin(), scene.insertion_points.end()), scene.insertion_points.end());
    // Images no element uses stay listed: the scene names every tileset image
    // so that ids do not depend on the viewport.
    return scene;
}

} // namespace depthcull::io
