// Small hand-built scenes for the render tests, and a trivially correct
// "optimized" output for them that does not depend on reconstruct_scene:
// every element's whole rect in the blended pass at its own depth, plus an
// opaque-pass quad over a rectangle of texels known to be fully opaque, a
// level nearer (paper 2.3.2's k + epsilon), drawn front to back.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "depthcull/scene.h"
#include "testing/ascii_image.h"

namespace depthcull::test {

struct RenderScene {
    Scene scene;
    std::vector<Image> images;
    std::vector<Rect> opaque_rects; // per image: texels all alpha 255 (may be empty)

    std::vector<ImageView> views() const {
        std::vector<ImageView> v;
        for (const Image& i : images) v.push_back(i.view());
        return v;
    }
    int add_image(Image image, Rect opaque) {
        // Distinct paths: elements share a mesh by image path (can_share_mesh).
        const std::string id = "img" + std::to_string(images.size());
        scene.images.push_back({id, id + ".png", image.width, image.height});
        images.push_back(std::move(image));
        opaque_rects.push_back(opaque);
        return int(images.size()) - 1;
    }
    Element& add(int image, std::array<double, 6> transform, Blend blend = Blend::alpha,
                 std::array<float, 4> color = {1, 1, 1, 1}) {
        Element e;
        e.image = image;
        e.rect = {0, 0, images[std::size_t(image)].width, images[std::size_t(image)].height};
        e.transform = transform;
        e.blend = blend;
        e.color = color;
        scene.elements.push_back(e);
        return scene.elements.back();
    }
};

inline std::array<double, 6> rotation(double degrees, double tx, double ty, double scale = 1) {
    const double r = degrees * 3.14159265358979323846 / 180;
    return {scale * std::cos(r), scale * std::sin(r), -scale * std::sin(r), scale * std::cos(r), tx, ty};
}

// A quad over texel rect `r` of element `element` (whose rect starts at
// its e.rect), sampling through element map `element` (an element span).
inline void add_quad(Draw& d, const Scene& scene, std::size_t element, Rect r, float z) {
    const Element& e = scene.elements[element];
    const SceneImage& img = scene.images[std::size_t(e.image)];
    const std::uint32_t base = std::uint32_t(d.vertex_count());
    const Vec2 corners[4] = {{double(r.x), double(r.y)},
                             {double(r.x + r.w), double(r.y)},
                             {double(r.x + r.w), double(r.y + r.h)},
                             {double(r.x), double(r.y + r.h)}};
    for (const Vec2& c : corners) {
        Vec2 s = apply(e.transform, {c.x - e.rect.x, c.y - e.rect.y});
        d.vertices.insert(d.vertices.end(), {float(s.x), float(s.y), z, float(c.x / img.width), float(c.y / img.height),
                                             e.color[0], e.color[1], e.color[2], e.color[3]});
    }
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) d.indices.push_back(base + i);
    d.element_spans.push_back({std::uint32_t(element), base});
}

// Meshes as read from a file: no element spans, so renderers fall back to
// per-triangle texel maps.
inline SceneMeshes without_element_maps(SceneMeshes m) {
    for (Draw& d : m.draws) d.element_spans.clear();
    return m;
}

// Element i gets depth (2i+1)/(2n+2) for its rect and (2i+2)/(2n+2) for its
// opaque quad: distinct 24-bit depth values for any n a test uses.
inline SceneMeshes hand_optimized(const RenderScene& rs) {
    const Scene& s = rs.scene;
    const std::size_t n = s.elements.size();
    SceneMeshes out;
    out.viewport = s.viewport;
    out.depth_test = true;
    auto depth = [&](std::size_t level) { return float(double(level) / double(2 * n + 2)); };
    for (std::size_t i = n; i-- > 0;) {
        const Element& e = s.elements[i];
        const Rect& o = rs.opaque_rects[std::size_t(e.image)];
        if (e.blend != Blend::alpha || e.color[3] != 1.0f || o.empty()) continue;
        Draw d;
        d.image = e.image;
        d.pass = Pass::opaque;
        d.blend = e.blend;
        add_quad(d, s, i, {e.rect.x + o.x, e.rect.y + o.y, o.w, o.h}, depth(2 * i + 2));
        out.draws.push_back(std::move(d));
    }
    for (std::size_t i = 0; i < n; ++i) {
        const Element& e = s.elements[i];
        Draw d;
        d.image = e.image;
        d.pass = Pass::blend;
        d.blend = e.blend;
        add_quad(d, s, i, e.rect, depth(2 * i + 1));
        out.draws.push_back(std::move(d));
    }
    return out;
}

// A sprite with a transparent margin, a translucent ring and an opaque
// core; texel colours vary with position (ascii_image) so a texel mix-up
// shows in the frame. Opaque core: texels [3, 9) x [2, 8).
inline Image test_sprite() {
    return ascii_image({
        "............",
        "..+++++++...",
        ".++######+..",
        ".+#######++.",
        ".+#######5+.",
        "..+######++.",
        "..+######+..",
        "..+######+..",
        "...++++++...",
        "....3..2....",
    });
}

// The scene most tests draw: rotated, scaled (up and down), flipped,
// atlas-framed, tinted, additive, multiplied and opaque-blended elements,
// overlapping in a 64x48 viewport that starts off the origin.
inline RenderScene mixed_scene() {
    RenderScene rs;
    rs.scene.viewport = {-3, 5, 64, 48};
    const int sprite = rs.add_image(test_sprite(), {3, 2, 6, 6});
    Image atlas = ascii_image({
        "########....++++",
        "########...+##++",
        "##....##..+####+",
        "##....##..+####+",
        "########...+##+.",
        "########....++..",
    });
    const int page = rs.add_image(std::move(atlas), {});
    Image block = ascii_image({"####", "####", "####"});
    const int solid = rs.add_image(std::move(block), {0, 0, 4, 3});

    rs.add(solid, {16, 0, 0, 16, -3, 5}, Blend::opaque);                 // background, scaled 16x
    rs.add(sprite, {1, 0, 0, 1, 2, 8});                                  // plain
    rs.add(sprite, {2, 0, 0, 2, 10, 12});                                // scaled up
    rs.add(sprite, {0.5, 0, 0, 0.5, 30, 6});                             // scaled down: centres on texel edges
    rs.add(sprite, {-1, 0, 0, 1, 40, 20});                               // flipped
    rs.add(sprite, {0, 1, -1, 0, 50, 10});                               // rotated 90
    rs.add(sprite, rotation(30, 22, 20, 1.5));                           // rotated 30, scaled
    rs.add(sprite, {1, 0, 0, 1, 14, 30}, Blend::alpha, {1, 0.5f, 0.25f, 1}); // tinted, still opaque
    rs.add(sprite, {1, 0, 0, 1, 18, 33}, Blend::alpha, {1, 1, 1, 0.5f}); // translucent tint
    rs.add(sprite, rotation(-60, 34, 34), Blend::add);                    // additive
    rs.add(sprite, {1.5, 0, 0, 1.5, 44, 28}, Blend::multiply);            // multiply
    Element& frame = rs.add(page, {1, 0, 0, 1, 0, 36});                   // atlas frame 1
    frame.rect = {0, 0, 8, 6};
    Element& frame2 = rs.add(page, {0, -1, 1, 0, 50, 46}, Blend::alpha); // atlas frame 2, rotated -90
    frame2.rect = {8, 0, 8, 6};
    rs.add(sprite, {1, 0, 0, -1, 26, 52});                               // flipped vertically, partly off-screen
    rs.add(sprite, {1, 0, 0, 1, 10.5, 20.25});                           // off the pixel grid
    return rs;
}

} // namespace depthcull::test
