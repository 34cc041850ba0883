// Hand-built scenes for the reconstruction tests: images are only sizes,
// analyses are given polygons, so each test states its geometry exactly.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "depthcull/scene.h"

namespace depthcull::test {

struct SceneBuilder {
    Scene scene;
    std::vector<std::unique_ptr<ImageAnalysis>> owned;
    std::vector<const ImageAnalysis*> analyses;

    SceneBuilder() { scene.viewport = {0, 0, 256, 256}; }

    int image(const std::string& id, int w, int h, std::string path = {}) {
        scene.images.push_back({id, path.empty() ? id + ".png" : path, w, h});
        return int(scene.images.size()) - 1;
    }
    // An analysis for the whole image: `boundary` / `opaque` in texels.
    const ImageAnalysis* analysis(int image, std::vector<Polygon> boundary, std::vector<Polygon> opaque = {}) {
        auto a = std::make_unique<ImageAnalysis>();
        a->rect = {0, 0, scene.images[std::size_t(image)].width, scene.images[std::size_t(image)].height};
        a->boundary = std::move(boundary);
        a->opaque = std::move(opaque);
        owned.push_back(std::move(a));
        return owned.back().get();
    }
    const ImageAnalysis* full(int image) {
        const SceneImage& img = scene.images[std::size_t(image)];
        double w = img.width, h = img.height;
        return analysis(image, {{{0, 0}, {w, 0}, {w, h}, {0, h}}});
    }
    const ImageAnalysis* full_opaque(int image) {
        const SceneImage& img = scene.images[std::size_t(image)];
        double w = img.width, h = img.height;
        Polygon r{{0, 0}, {w, 0}, {w, h}, {0, h}};
        return analysis(image, {r}, {r});
    }
    std::size_t add(int image, const ImageAnalysis* a, double x, double y, Blend blend = Blend::alpha, float alpha = 1.0f) {
        Element e;
        e.image = image;
        e.rect = {0, 0, scene.images[std::size_t(image)].width, scene.images[std::size_t(image)].height};
        e.transform = {1, 0, 0, 1, x, y};
        e.color = {1, 1, 1, alpha};
        e.blend = blend;
        scene.elements.push_back(e);
        analyses.push_back(a);
        return scene.elements.size() - 1;
    }
};

inline std::vector<std::pair<int, int>> edges_of(const ElementGraph& g) {
    std::vector<std::pair<int, int>> out;
    for (std::size_t i = 0; i < g.size(); ++i)
        for (const std::uint32_t* b = g.behind_begin(i); b != g.behind_end(i); ++b) out.push_back({int(i), int(*b)});
    return out;
}

} // namespace depthcull::test
