#include "testing/random_shapes.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace depthcull::test {

namespace {

void paint(Image& image, int x, int y, std::uint8_t alpha, bool max_blend) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    std::uint8_t* t = &image.rgba[(std::size_t(y) * image.width + x) * 4];
    t[0] = std::uint8_t(x * 13 + y * 7);
    t[1] = std::uint8_t(x * 5 + 100);
    t[2] = std::uint8_t(y * 11 + 50);
    t[3] = max_blend ? std::max(t[3], alpha) : alpha;
}

} // namespace

Image random_shape(std::uint64_t seed, const ShapeParams& p) {
    std::mt19937_64 rng(seed);
    Image image;
    image.width = std::max(1, p.width);
    image.height = std::max(1, p.height);
    image.rgba.assign(std::size_t(image.width) * image.height * 4, 0);
    auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    auto shape = [&](bool hole) {
        int kind = int(rng() % 3);
        double cx = uni(-0.1, 1.1) * image.width, cy = uni(-0.1, 1.1) * image.height;
        double r = uni(0.05, 0.5) * std::max(image.width, image.height);
        double ax = uni(-1, 1), ay = uni(-1, 1), bx = uni(-1, 1), by = uni(-1, 1);
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                double px = x + 0.5 - cx, py = y + 0.5 - cy, d;
                if (kind == 0) d = std::hypot(px, py) - r;
                else if (kind == 1) d = std::max(std::abs(px) - r, std::abs(py) - r * 0.6);
                else {
                    // triangle: centre and two corners
                    double e1 = (px * ay - py * ax), e2 = (px * by - py * bx);
                    d = std::max({-e1 * r, e2 * r, std::hypot(px, py) - r});
                    d = d > 0 ? 1 : -1;
                }
                if (hole) {
                    if (d < 0) paint(image, x, y, 0, false);
                } else if (d < 0) {
                    paint(image, x, y, 255, true);
                } else if (p.translucent_rim && d < 1.5) {
                    paint(image, x, y, std::uint8_t(40 + rng() % 200), true);
                }
            }
    };
    for (int i = 0; i < p.blobs; ++i) shape(false);
    for (int i = 0; i < p.holes; ++i) shape(true);
    if (p.noise) {
        int n = int(rng() % (image.width * image.height / 16 + 1));
        for (int i = 0; i < n; ++i) paint(image, int(rng() % image.width), int(rng() % image.height), std::uint8_t(rng() % 256), false);
    }
    return image;
}

rc::Gen<Image> gen_shape(int max_side) {
    return rc::gen::apply(
        [](std::uint64_t seed, int w, int h, int blobs, int holes, bool rim, bool noise) {
            ShapeParams p{w, h, blobs, holes, rim, noise};
            return random_shape(seed, p);
        },
        rc::gen::arbitrary<std::uint64_t>(), rc::gen::inRange(1, max_side + 1), rc::gen::inRange(1, max_side + 1),
        rc::gen::inRange(0, 5), rc::gen::inRange(0, 3), rc::gen::arbitrary<bool>(),
        rc::gen::weightedOneOf<bool>({{4, rc::gen::just(false)}, {1, rc::gen::just(true)}}));
}

} // namespace depthcull::test
