// Our scene format (issue 4):
//   { "viewport": {"x", "y", "width", "height"},   // x, y optional
//     "filter": "nearest" | "linear",              // optional
//     "images": [ {"id", "path"} | {"id", "atlas"} ],   // paths relative to the scene file
//     "elements": [ {"image", "rect"?, "frame"?, "transform"?, "color"?, "blend"?} ],
//     "insertion_points": [element index, ...] }   // optional: where moving sprites go
// Unknown fields are ignored. Every bad value is an Error naming the
// file and the element (or image) index; nothing is half-loaded.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "depthcull/limits.h"
#include "io/formats.h"

namespace depthcull::io {

namespace {

std::string number_text(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::size_t kMaxImages = limits::kMaxSceneImages;
constexpr std::size_t kMaxElements = std::size_t(limits::kMaxSceneElements);

struct Context {
    std::string file;
    std::string where; // "element 3: "
    [[noreturn]] void fail(const std::string& what) const { throw Error(file + ": " + where + what); }
};

std::string resolve(const fs::path& base_dir, const std::string& p) {
    fs::path path(p);
    if (path.is_absolute() || base_dir.empty()) return path.lexically_normal().string();
    return (base_dir / path).lexically_normal().string();
}

double number(const Context& ctx, const json& v, const char* what) {
    if (!v.is_number()) ctx.fail(std::string(what) + " must be a number");
    double d = v.get<double>();
    if (!std::isfinite(d)) ctx.fail(std::string(what) + " must be finite");
    return d;
}

int integer(const Context& ctx, const json& v, const char* what) {
    double d = number(ctx, v, what);
    if (d != std::floor(d) || std::fabs(d) > double(1 << 30)) ctx.fail(std::string(what) + " must be an integer");
    return int(d);
}

const std::string& string_field(const Context& ctx, const json& obj, const char* key) {
    auto it = obj.find(key);
    if (it == obj.end()) ctx.fail(std::string("missing \"") + key + "\"");
    if (!it->is_string()) ctx.fail(std::string("\"") + key + "\" must be a string");
    return it->get_ref<const std::string&>();
}

template <std::size_t N>
std::array<double, N> number_array(const Context& ctx, const json& v, const char* key) {
    if (!v.is_array() || v.size() != N) ctx.fail(std::string("\"") + key + "\" must be an array of " + std::to_string(N) + " numbers");
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = number(ctx, v[i], key);
    return out;
}

Viewport parse_viewport(const Context& ctx, const json& v) {
    Context c = ctx;
    c.where = "viewport: ";
    if (!v.is_object()) c.fail("must be an object");
    Viewport vp;
    if (v.contains("x")) vp.x = number(c, v["x"], "x");
    if (v.contains("y")) vp.y = number(c, v["y"], "y");
    if (std::fabs(vp.x) > limits::kMaxCoordinate || std::fabs(vp.y) > limits::kMaxCoordinate)
        c.fail("x and y must be within +-1e9 (kMaxCoordinate)");
    if (!v.contains("width") || !v.contains("height")) c.fail("needs \"width\" and \"height\"");
    vp.width = integer(c, v["width"], "width");
    vp.height = integer(c, v["height"], "height");
    if (vp.width <= 0 || vp.height <= 0 || vp.width > kMaxImageSide || vp.height > kMaxImageSide)
        c.fail("width and height must be 1.." + std::to_string(kMaxImageSide));
    return vp;
}

Blend parse_blend(const Context& ctx, const json& v) {
    static const std::map<std::string, Blend> names{
        {"alpha", Blend::alpha}, {"add", Blend::add}, {"multiply", Blend::multiply}, {"opaque", Blend::opaque}};
    if (!v.is_string()) ctx.fail("\"blend\" must be a string");
    auto it = names.find(v.get<std::string>());
    if (it == names.end()) ctx.fail("unknown blend \"" + v.get<std::string>() + "\" (expected alpha, add, multiply or opaque)");
    return it->second;
}

struct ImageEntry {
    bool is_atlas = false;
    Atlas atlas;
    std::vector<int> page_images; // a multipack's pages: scene image per page (page 0: the entry's own)
};

Element parse_element(const Context& ctx, const json& v, const Scene& scene, const std::map<std::string, int>& ids,
                      const std::vector<ImageEntry>& entries) {
    if (!v.is_object()) ctx.fail("must be an object");
    Element e;
    const std::string& id = string_field(ctx, v, "image");
    auto it = ids.find(id);
    if (it == ids.end()) ctx.fail("unknown image id \"" + id + "\"");
    e.image = it->second;
    const SceneImage* page = &scene.images[std::size_t(e.image)];
    const SceneImage& img = *page;
    if (v.contains("transform")) {
        e.transform = number_array<6>(ctx, v["transform"], "transform");
        // Far beyond any screen, and keeps every product finite.
        for (double t : e.transform)
            if (std::fabs(t) > limits::kMaxCoordinate) ctx.fail("\"transform\" values must be within +-1e9 (kMaxCoordinate)");
    }
    if (v.contains("color")) {
        auto c = number_array<4>(ctx, v["color"], "color");
        for (std::size_t k = 0; k < 4; ++k) {
            if (c[k] < 0 || c[k] > 1) ctx.fail("\"color\" components must be in 0..1");
            e.color[k] = float(c[k]);
        }
    }
    if (v.contains("blend")) e.blend = parse_blend(ctx, v["blend"]);
    if (v.contains("frame")) {
        const ImageEntry& entry = entries[std::size_t(e.image)];
        if (!entry.is_atlas) ctx.fail("\"frame\" needs an atlas image, \"" + id + "\" is not one");
        if (!v["frame"].is_string()) ctx.fail("\"frame\" must be a string");
        const AtlasFrame* frame = entry.atlas.find(v["frame"].get<std::string>());
        if (!frame) ctx.fail("atlas \"" + id + "\" has no frame \"" + v["frame"].get<std::string>() + "\"");
        if (!entry.page_images.empty()) {
            e.image = entry.page_images[std::size_t(frame->page)];
            page = &scene.images[std::size_t(e.image)];
        }
        FramePlacement placed = place_frame(*frame, e.transform);
        e.rect = placed.rect;
        e.transform = placed.transform;
    } else if (v.contains("rect")) {
        const json& r = v["rect"];
        if (!r.is_array() || r.size() != 4) ctx.fail("\"rect\" must be [x, y, w, h]");
        e.rect = {integer(ctx, r[0], "rect"), integer(ctx, r[1], "rect"), integer(ctx, r[2], "rect"), integer(ctx, r[3], "rect")};
        if (e.rect.w <= 0 || e.rect.h <= 0) ctx.fail("\"rect\" must have a positive size");
    } else {
        e.rect = {0, 0, img.width, img.height};
    }
    if (!ImageView{nullptr, page->width, page->height, 0}.contains(e.rect) || e.rect.empty())
        ctx.fail("rect " + std::to_string(e.rect.x) + "," + std::to_string(e.rect.y) + "," + std::to_string(e.rect.w) + "," +
                 std::to_string(e.rect.h) + " is outside the " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                 " image \"" + id + "\"");
    return e;
}

// The elements' screen bounds, for scenes that name no viewport.
Viewport bounding_viewport(const Scene& scene) {
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (const Element& e : scene.elements) {
        for (Vec2 c : {Vec2{0, 0}, Vec2{double(e.rect.w), 0}, Vec2{0, double(e.rect.h)}, Vec2{double(e.rect.w), double(e.rect.h)}}) {
            Vec2 s = apply(e.transform, c);
            x0 = std::min(x0, s.x), y0 = std::min(y0, s.y), x1 = std::max(x1, s.x), y1 = std::max(y1, s.y);
        }
    }
    Viewport vp;
    if (scene.elements.empty()) return {0, 0, 1, 1};
    vp.x = std::floor(x0);
    vp.y = std::floor(y0);
    vp.width = int(std::clamp(std::ceil(x1) - vp.x, 1.0, double(kMaxImageSide)));
    vp.height = int(std::clamp(std::ceil(y1) - vp.y, 1.0, double(kMaxImageSide)));
    return vp;
}

// The "images" array, in order: ids, paths (or atlases, or fills) and sizes.
void parse_images(const json& images, const std::string& path, const fs::path& base, const LoadOptions& options, Scene& scene,
                  std::map<std::string, int>& ids, std::vector<ImageEntry>& entries) {
    for (std::size_t i = 0; i < images.size(); ++i) {
        Context c{path, "image " + std::to_string(i) + ": "};
        const json& v = images[i];
        if (!v.is_object()) c.fail("must be an object");
        SceneImage img;
        img.id = string_field(c, v, "id");
        if (!ids.emplace(img.id, int(i)).second) c.fail("duplicate image id \"" + img.id + "\"");
        if (v.contains("atlas")) {
            entries[i].is_atlas = true;
            const std::string atlas = resolve(base, string_field(c, v, "atlas"));
            if (options.documents) options.documents->push_back(atlas);
            entries[i].atlas = read_atlas(atlas);
            img.path = entries[i].atlas.image_path;
        } else if (v.contains("fill")) {
            img.has_fill = true;
            img.fill = parse_color_key(string_field(c, v, "fill"), path + ": image " + std::to_string(i));
        } else {
            img.path = resolve(base, string_field(c, v, "path"));
        }
        if (v.contains("trans")) {
            img.has_trans = true;
            img.trans = parse_color_key(string_field(c, v, "trans"), path + ": image " + std::to_string(i));
        }
        try {
            if (img.has_fill) img.width = img.height = kFillImageSide;
            else image_size(img.path, &img.width, &img.height, options.image_files);
        } catch (const Error& e) {
            c.fail(e.what());
        }
        scene.images.push_back(std::move(img));
    }
}

// A multipack atlas's other pages: images "<id>#<page>" after the listed ones.
void add_atlas_pages(const Context& ctx, std::size_t listed, const LoadOptions& options, Scene& scene, std::map<std::string, int>& ids,
                     std::vector<ImageEntry>& entries) {
    for (std::size_t i = 0; i < listed; ++i) {
        ImageEntry& entry = entries[i];
        if (!entry.is_atlas) continue;
        std::vector<std::array<int, 2>> sizes{{scene.images[i].width, scene.images[i].height}};
        if (entry.atlas.pages.size() >= 2) entry.page_images.push_back(int(i));
        for (std::size_t k = 1; k < entry.atlas.pages.size(); ++k) {
            SceneImage img;
            img.id = scene.images[i].id + "#" + std::to_string(k);
            if (!ids.emplace(img.id, int(scene.images.size())).second)
                ctx.fail("image id \"" + img.id + "\" (page " + std::to_string(k) + " of atlas \"" + scene.images[i].id + "\") is taken");
            img.path = entry.atlas.pages[k].image_path;
            image_size(img.path, &img.width, &img.height, options.image_files);
            sizes.push_back({img.width, img.height});
            entry.page_images.push_back(int(scene.images.size()));
            scene.images.push_back(std::move(img));
        }
        // Frames against the pages' real sizes (the headers just read);
        // what the atlas reader assumed is warned (or refused, --strict).
        check_atlas_pages(entry.atlas, sizes);
        if (entry.atlas.scale != 1)
            entry.atlas.warnings.push_back(entry.atlas.path + ": meta.scale " + number_text(entry.atlas.scale) +
                                           ": frames placed at their texel size, as Phaser places them (PixiJS draws them " +
                                           (entry.atlas.scale > 0 ? number_text(1 / entry.atlas.scale) + "x" : "at another size") + ")");
        report_warnings(entry.atlas.warnings, options);
    }
}

// "animations": frames of one size, each an image rect and a duration.
void parse_animations(const Context& ctx, const json& animations, const std::string& path, const std::map<std::string, int>& ids,
                      Scene& scene) {
    if (!animations.is_array() || animations.size() > kMaxElements) ctx.fail("\"animations\" must be an array");
    for (std::size_t i = 0; i < animations.size(); ++i) {
        Context c{path, "animation " + std::to_string(i) + ": "};
        const json& a = animations[i];
        if (!a.is_object() || !a.contains("frames") || !a["frames"].is_array() || a["frames"].empty() || a["frames"].size() > 65536)
            c.fail("must be an object with a non-empty \"frames\" array");
        Animation animation;
        for (const json& f : a["frames"]) {
            if (!f.is_object()) c.fail("frame must be an object");
            const std::string& id = string_field(c, f, "image");
            auto it = ids.find(id);
            if (it == ids.end()) c.fail("unknown image id \"" + id + "\"");
            const SceneImage& img = scene.images[std::size_t(it->second)];
            if (!f.contains("rect") || !f["rect"].is_array() || f["rect"].size() != 4) c.fail("frame \"rect\" must be [x, y, w, h]");
            const json& r = f["rect"];
            Rect rect{integer(c, r[0], "rect"), integer(c, r[1], "rect"), integer(c, r[2], "rect"), integer(c, r[3], "rect")};
            if (rect.empty() || !ImageView{nullptr, img.width, img.height, 0}.contains(rect)) c.fail("frame rect is outside image \"" + id + "\"");
            if (!animation.frames.empty() && (rect.w != animation.frames[0].rect.w || rect.h != animation.frames[0].rect.h))
                c.fail("frames differ in size");
            int duration = f.contains("duration") ? integer(c, f["duration"], "duration") : 0;
            if (duration < 0) c.fail("negative duration");
            animation.frames.push_back({it->second, rect, duration});
        }
        scene.animations.push_back(std::move(animation));
    }
}

} // namespace

Scene scene_json_from_text(std::string_view text, const std::string& path, const LoadOptions& options) {
    Context ctx{path, ""};
    json doc;
    try {
        check_json_depth(text, path);
        doc = json::parse(text);
    } catch (const json::exception& e) {
        // parse_error, and out_of_range for numbers like 1e400.
        throw_json_error(e, text, path);
    }
    if (!doc.is_object()) ctx.fail("expected a JSON object with \"images\" and \"elements\"");
    const fs::path base = fs::path(path).parent_path();
    Scene scene;
    if (doc.contains("filter")) {
        const json& f = doc["filter"];
        if (f == "nearest") scene.filter = Filter::nearest;
        else if (f == "linear") scene.filter = Filter::linear;
        else ctx.fail("\"filter\" must be \"nearest\" or \"linear\"");
    }

    if (!doc.contains("images") || !doc["images"].is_array()) ctx.fail("missing \"images\" array");
    if (!doc.contains("elements") || !doc["elements"].is_array()) ctx.fail("missing \"elements\" array");
    const json& images = doc["images"];
    const json& elements = doc["elements"];
    if (images.size() > kMaxImages) ctx.fail("more than " + std::to_string(kMaxImages) + " images (kMaxSceneImages)");
    if (elements.size() > kMaxElements) ctx.fail("more than " + std::to_string(kMaxElements) + " elements (kMaxSceneElements)");

    std::map<std::string, int> ids;
    std::vector<ImageEntry> entries(images.size());
    parse_images(images, path, base, options, scene, ids, entries);
    add_atlas_pages(ctx, images.size(), options, scene, ids, entries);
    if (doc.contains("animations")) parse_animations(ctx, doc["animations"], path, ids, scene);
    scene.elements.reserve(elements.size());
    for (std::size_t i = 0; i < elements.size(); ++i) {
        Context c{path, "element " + std::to_string(i) + ": "};
        scene.elements.push_back(parse_element(c, elements[i], scene, ids, entries));
        if (elements[i].contains("animation")) {
            Element& e = scene.elements.back();
            e.animation = integer(c, elements[i]["animation"], "animation");
            if (e.animation < 0 || std::size_t(e.animation) >= scene.animations.size()) c.fail("\"animation\" names no animation");
            const AnimationFrame& first = scene.animations[std::size_t(e.animation)].frames.front();
            if (first.image != e.image || first.rect != e.rect) c.fail("an animated element shows its animation's first frame (image and rect)");
        }
    }

    // Where moving sprites go (Scene::insertion_points): element indices,
    // each at most the element count (on top), kept in ascending order.
    if (doc.contains("insertion_points")) {
        const json& points = doc["insertion_points"];
        if (!points.is_array() || points.size() > kMaxElements) ctx.fail("\"insertion_points\" must be an array of element indices");
        for (std::size_t k = 0; k < points.size(); ++k) {
            const json& v = points[k];
            if (!v.is_number_integer() || v.get<std::int64_t>() < 0 || v.get<std::uint64_t>() > scene.elements.size())
                ctx.fail("insertion point " + std::to_string(k) + ": must be an element index in 0.." + std::to_string(scene.elements.size()) +
                         " (" + std::to_string(scene.elements.size()) + ": on top)");
            scene.insertion_points.push_back(v.get<std::size_t>());
        }
        std::sort(scene.insertion_points.begin(), scene.insertion_points.end());
        scene.insertion_points.erase(std::unique(scene.insertion_points.begin(), scene.insertion_points.end()), scene.insertion_points.end());
    }
    if (options.has_viewport) scene.viewport = options.viewport;
    else if (doc.contains("viewport")) scene.viewport = parse_viewport(ctx, doc["viewport"]);
    else scene.viewport = bounding_viewport(scene);
    return scene;
}

} // namespace depthcull::io
