// The scene reader on random, mostly wrong, field values: it either loads
// a valid scene or throws depthcull::Error with a one-line message; it never
// crashes or lets another exception out.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <rapidcheck/gtest.h>

#include "test_scene_json_helpers.h"

namespace depthcull::test {
namespace {

using nlohmann::json;

rc::Gen<json> gen_value() {
    return rc::gen::oneOf(rc::gen::just(json(nullptr)), rc::gen::map(rc::gen::arbitrary<bool>(), [](bool b) { return json(b); }),
                          rc::gen::map(rc::gen::inRange(-20, 40), [](int i) { return json(i); }),
                          rc::gen::map(rc::gen::element(0.5, -1.0, 1e300, 2.0), [](double d) { return json(d); }),
                          rc::gen::map(rc::gen::element<std::string>("blob", "tiles", "alpha", "add", "x", ""), [](std::string s) { return json(s); }),
                          rc::gen::map(rc::gen::container<std::vector<int>>(rc::gen::inRange(-4, 20)), [](std::vector<int> v) { return json(v); }));
}

RC_GTEST_PROP(SceneJsonFuzz, OnlyCleanErrors, ()) {
    static SceneDir dir("scene_json_fuzz");
    static bool art = (dir.standard_art(), true);
    (void)art;
    json elements = json::array();
    const int n = *rc::gen::inRange(0, 4);
    for (int i = 0; i < n; ++i) {
        json e = json::object();
        e["image"] = *rc::gen::oneOf(rc::gen::just(json("blob")), rc::gen::just(json("tiles")), gen_value());
        for (const char* key : {"rect", "transform", "color", "blend", "frame"})
            if (*rc::gen::inRange(0, 3) == 0) e[key] = *gen_value();
        elements.push_back(*rc::gen::inRange(0, 10) == 0 ? *gen_value() : e);
    }
    json scene = {{"images", json::array({{{"id", "blob"}, {"path", "art/blob.png"}}, {{"id", "tiles"}, {"path", "art/tiles.png"}}})},
                  {"elements", elements}};
    if (*rc::gen::inRange(0, 4) == 0) scene["viewport"] = *gen_value();
    if (*rc::gen::inRange(0, 4) == 0) scene["filter"] = *gen_value();
    std::string path = dir.write("fuzz.json", scene.dump());
    try {
        Scene s = io::read_scene(path);
        for (const Element& e : s.elements) {
            const SceneImage& img = s.images[std::size_t(e.image)];
            const ImageView view{nullptr, img.width, img.height, 0};
            RC_ASSERT(view.contains(e.rect));
            RC_ASSERT(!e.rect.empty());
        }
    } catch (const depthcull::Error& e) {
        RC_ASSERT(std::string(e.what()).find('\n') == std::string::npos);
    }
}

} // namespace
} // namespace depthcull::test
