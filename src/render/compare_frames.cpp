// Comparing frames of one scene: how many pixels differ, and whether
// rounding near an edge explains each difference.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "depthcull/render.h"

namespace depthcull::render {

ImageDiff compare_images(ImageView a, ImageView b) {
    ImageDiff diff;
    if (a.width != b.width || a.height != b.height) {
        diff.same_size = false;
        return diff;
    }
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            const std::uint8_t *p = a.texel(x, y), *q = b.texel(x, y);
            int worst = 0;
            for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(int(p[c]) - int(q[c])));
            if (worst) ++diff.pixels_differ;
            diff.max_channel_diff = std::max(diff.max_channel_diff, worst);
        }
    }
    return diff;
}

} // namespace depthcull::render

namespace depthcull::render {

namespace {

// Squared distance from p to segment ab.
double distance2(double px, double py, double ax, double ay, double bx, double by) {
    const double dx = bx - ax, dy = by - ay;
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    const double ex = ax + t * dx - px, ey = ay + t * dy - py;
    return ex * ex + ey * ey;
}

// Marks pixels whose centre lies within `tolerance` of an edge of any
// triangle, walking each edge along its major axis, so the cost is the
// total edge length, not pixels * triangles.
void mark_edges(const SceneMeshes& meshes, double tolerance, int width, int height, std::vector<std::uint8_t>& mask) {
    const double tol2 = tolerance * tolerance;
    auto mark = [&](int x, int y, double ax, double ay, double bx, double by) {
        if (x < 0 || y < 0 || x >= width || y >= height) return;
        if (distance2(x + 0.5, y + 0.5, ax, ay, bx, by) <= tol2) mask[std::size_t(y) * std::size_t(width) + std::size_t(x)] = 1;
    };
    for (const Draw& d : meshes.draws) {
        for (std::size_t t = 0; t + 3 <= d.indices.size(); t += 3) {
            double x[3], y[3];
            bool valid = true;
            for (int k = 0; k < 3 && valid; ++k) {
                const std::uint32_t i = d.indices[t + std::size_t(k)];
                valid = i < d.vertex_count();
                if (!valid) break;
                x[k] = double(d.vertices[std::size_t(i) * kVertexFloats]) - meshes.viewport.x;
                y[k] = double(d.vertices[std::size_t(i) * kVertexFloats + 1]) - meshes.viewport.y;
            }
            if (!valid) continue;
            for (int k = 0; k < 3; ++k) {
                const double ax = x[k], ay = y[k], bx = x[(k + 1) % 3], by = y[(k + 1) % 3];
                const bool steep = std::abs(by - ay) > std::abs(bx - ax);
                // Major axis m, minor axis n: visit each pixel column (row) the
                // edge spans and the pixels either side of it.
                const double m0 = steep ? std::min(ay, by) : std::min(ax, bx), m1 = steep ? std::max(ay, by) : std::max(ax, bx);
                const int limit = steep ? height : width;
                const int c0 = std::max(0, int(std::floor(m0 - tolerance - 0.5))), c1 = std::min(limit - 1, int(std::ceil(m1 + tolerance - 0.5)));
                for (int c = c0; c <= c1; ++c) {
                    const double m = c + 0.5;
                    const double am = steep ? ay : ax, bm = steep ? by : bx, an = steep ? ax : ay, bn = steep ? bx : by;
                    const double f = bm != am ? std::clamp((m - am) / (bm - am), 0.0, 1.0) : 0.0;
                    const double n = an + f * (bn - an);
                    for (int r = int(std::floor(n - 1.5)); r <= int(std::ceil(n + 0.5)); ++r) {
                        if (steep) mark(r, c, ax, ay, bx, by);
                        else mark(c, r, ax, ay, bx, by);
                    }
                }
            }
        }
    }
}

// True when the centre of pixel (x, y) lies inside the rect of an element
// of `scene` and within `tolerance` pixels (on screen) of one of its texel
// edges.
bool near_texel_edge(const Scene& scene, int x, int y, double tolerance) {
    const double px = scene.viewport.x + x + 0.5, py = scene.viewport.y + y + 0.5;
    for (const Element& e : scene.elements) {
        const auto& m = e.transform;
        const double det = m[0] * m[3] - m[1] * m[2];
        if (!(det != 0) || !std::isfinite(det)) continue;
        const double qx = px - m[4], qy = py - m[5];
        const double u = (m[3] * qx - m[2] * qy) / det, v = (m[0] * qy - m[1] * qx) / det;
        if (!(u >= -tolerance && v >= -tolerance && u <= e.rect.w + tolerance && v <= e.rect.h + tolerance)) continue;
        // |grad u| and |grad v| in texels per pixel turn texel distances into pixels.
        const double grad_u = std::hypot(m[3], m[2]) / std::abs(det), grad_v = std::hypot(m[1], m[0]) / std::abs(det);
        if (std::abs(u - std::round(u)) <= tolerance * grad_u || std::abs(v - std::round(v)) <= tolerance * grad_v) return true;
    }
    return false;
}

} // namespace

DiffCauses classify_differences(ImageView a, const SceneMeshes& meshes_a, ImageView b, const SceneMeshes& meshes_b, const Scene* scene,
                                double tolerance) {
    DiffCauses causes;
    if (a.width != b.width || a.height != b.height) {
        causes.elsewhere = std::int64_t(std::max(a.width, b.width)) * std::max(a.height, b.height);
        return causes;
    }
    std::vector<std::uint8_t> near;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            if (std::equal(a.texel(x, y), a.texel(x, y) + 4, b.texel(x, y))) continue;
            if (near.empty()) { // only frames that differ pay for the edge mask
                near.assign(std::size_t(a.width) * std::size_t(a.height), 0);
                mark_edges(meshes_a, tolerance, a.width, a.height, near);
                mark_edges(meshes_b, tolerance, a.width, a.height, near);
            }
            if (near[std::size_t(y) * std::size_t(a.width) + std::size_t(x)] || (scene && near_texel_edge(*scene, x, y, tolerance)))
                ++causes.near_edges;
            else ++causes.elsewhere;
        }
    }
    return causes;
}

} // namespace depthcull::render
