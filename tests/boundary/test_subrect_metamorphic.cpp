// Metamorphic test (manifold style), exact: analyzing a sub-rectangle of an
// image equals analyzing that rectangle cropped out as an image of its own,
// with every polygon vertex moved by the rect's offset and the same stats.
// The analysis cache keys an entry by the rect's texels and size, not its
// position (equal tiles anywhere share one entry), so this must hold for
// every image, rect, budget, filter and opaque method.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "depthcull/analyze.h"
#include "testing/random_shapes.h"

using namespace depthcull;

namespace {

Image crop(const Image& in, Rect r) {
    Image out;
    out.width = r.w;
    out.height = r.h;
    out.rgba.resize(std::size_t(r.w) * std::size_t(r.h) * 4);
    for (int y = 0; y < r.h; ++y)
        for (int x = 0; x < r.w; ++x)
            for (int c = 0; c < 4; ++c)
                out.rgba[(std::size_t(y) * std::size_t(r.w) + std::size_t(x)) * 4 + std::size_t(c)] =
                    in.rgba[(std::size_t(r.y + y) * std::size_t(in.width) + std::size_t(r.x + x)) * 4 + std::size_t(c)];
    return out;
}

std::vector<Polygon> moved(std::vector<Polygon> polygons, double dx, double dy) {
    for (Polygon& p : polygons)
        for (Vec2& v : p) v = {v.x + dx, v.y + dy};
    return polygons;
}

} // namespace

RC_GTEST_PROP(SubRectMetamorphic, SubRectAnalysisIsTheCroppedImagesOffset, ()) {
    const Image image = *test::gen_shape(40);
    const int x = *rc::gen::inRange(0, image.width), y = *rc::gen::inRange(0, image.height);
    const int w = *rc::gen::inRange(1, image.width - x + 1), h = *rc::gen::inRange(1, image.height - y + 1);
    const Rect rect{x, y, w, h};
    AnalyzeOptions o;
    o.boundary.max_vertices = *rc::gen::inRange(4, 13);
    o.boundary.split_parts = *rc::gen::arbitrary<bool>();
    o.filter = *rc::gen::element(Filter::nearest, Filter::linear);
    o.opaque.method = *rc::gen::element(OpaqueMethod::fast, OpaqueMethod::grow, OpaqueMethod::paper);
    o.opaque.min_area = *rc::gen::inRange(1, 65);

    const ImageAnalysis in_place = analyze_image(image.view(), rect, o);
    const Image cropped = crop(image, rect);
    const ImageAnalysis alone = analyze_image(cropped.view(), cropped.view().bounds(), o);

    RC_ASSERT(in_place.rect == rect);
    RC_ASSERT(in_place.boundary == moved(alone.boundary, x, y));
    RC_ASSERT(in_place.opaque == moved(alone.opaque, x, y));
    // Every figure, exactly (ImageStats holds no wall time to differ).
    RC_ASSERT(in_place.stats == alone.stats);
    // And a second run is the same value.
    RC_ASSERT(analyze_image(image.view(), rect, o) == in_place);
}
