// Expectations the Tiled reader tests share (test_tiled.cpp: TMX;
// test_tiled_formats.cpp: the JSON forms and newer features).
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <string>

#include "depthcull/scene.h"
#include "testing/corpus.h"

namespace depthcull::test {

using T = std::array<double, 6>;

inline std::string data(const std::string& name) { return source_path("tests/data/tiled/" + name); }

inline void expect_element(const Scene& s, std::size_t i, const std::string& image, Rect rect, T transform,
                    std::array<float, 4> color = {1, 1, 1, 1}, Blend blend = Blend::alpha) {
    ASSERT_LT(i, s.elements.size());
    const Element& e = s.elements[i];
    EXPECT_EQ(s.images.at(std::size_t(e.image)).id, image) << "element " << i;
    EXPECT_EQ(e.rect, rect) << "element " << i << " rect " << e.rect.x << "," << e.rect.y << "," << e.rect.w << "," << e.rect.h;
    for (int k = 0; k < 6; ++k) EXPECT_DOUBLE_EQ(e.transform[std::size_t(k)], transform[std::size_t(k)]) << "element " << i << " transform[" << k << "]";
    for (int k = 0; k < 4; ++k) EXPECT_FLOAT_EQ(e.color[std::size_t(k)], color[std::size_t(k)]) << "element " << i << " color[" << k << "]";
    EXPECT_EQ(e.blend, blend) << "element " << i;
}

// The 3x2 map every encoding test stores: gids 1, 2|H, 0 / 3|V, 4|D, 2.
inline void expect_flips_map(const Scene& s) {
    ASSERT_EQ(s.images.size(), 1u);
    EXPECT_EQ(s.images[0].id, "tiles");
    EXPECT_EQ(s.images[0].width, 12);
    EXPECT_EQ(s.images[0].height, 12);
    EXPECT_EQ(s.viewport.x, 0);
    EXPECT_EQ(s.viewport.y, 0);
    EXPECT_EQ(s.viewport.width, 12);
    EXPECT_EQ(s.viewport.height, 8);
    ASSERT_EQ(s.elements.size(), 5u);
    expect_element(s, 0, "tiles", {1, 1, 4, 4}, {1, 0, 0, 1, 0, 0});
    expect_element(s, 1, "tiles", {6, 1, 4, 4}, {-1, 0, 0, 1, 8, 0});  // horizontal flip
    expect_element(s, 2, "tiles", {1, 6, 4, 4}, {1, 0, 0, -1, 0, 8});  // vertical flip
    expect_element(s, 3, "tiles", {6, 6, 4, 4}, {0, 1, 1, 0, 4, 4});   // anti-diagonal: transpose
    expect_element(s, 4, "tiles", {6, 1, 4, 4}, {1, 0, 0, 1, 8, 4});
}

} // namespace depthcull::test
