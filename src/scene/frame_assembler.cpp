// FrameAssembler (depthcull/frame.h): moving sprites depth-culled every
// frame. Each sprite follows the rules reconstruction gives an element
// (shapes.cpp), and its vertices are the ones MeshBuilder would make for
// it (the same texel-space polygons, texel skirts and pulled-in opaque
// polygons, transformed the same way), so a frame draws pixel for pixel
// like overpaint in a plain renderer (texel_margin.cpp says why). The one
// difference is cheaper: the skirts take the joined form, welded, where a
// convex polygon and its skirt are one dilated polygon (texel_margin.cpp),
// covering the same points, so a sprite is a template of few vertices that
// a frame only transforms.
//
// Depth: sprite i of a frame (or of an insertion point) gets level
// first + i, one per sprite in painter's order. That needs no graph: each
// sprite is in front of every sprite before it, which is all the painter's
// order asks. The graph is needed only to batch the blend pass: a sprite may
// join an earlier draw of its texture unless it overlaps a sprite drawn in
// between. Overlap is tested on a grid of screen cells holding, per cell,
// the latest batch any sprite there joined; a sprite covering more than
// cell_budget cells counts as overlapping everything, so the work per
// sprite is bounded (batching degrades, correctness never does).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

#include "depthcull/frame.h"
#include "depthcull/limits.h"
#include "scene/internal.h"
#include "scene/placement.h"

// SSE2 streaming stores for frame vertices (x86-64 always has SSE2);
// elsewhere (WebAssembly, ARM) plain stores.
#if defined(__SSE2__) && !defined(__EMSCRIPTEN__)
#include <emmintrin.h>
#define DEPTHCULL_STREAM_VERTICES 1
#else
#define DEPTHCULL_STREAM_VERTICES 0
#endif
// SSE2 also for the overlap grid (FrameAssembler::run).
#define DEPTHCULL_SSE2_GRID DEPTHCULL_STREAM_VERTICES

namespace {
// Frames whose vertices take more than this stream them past the caches
// (emit_groups); smaller ones stay cached for the upload.
constexpr std::size_t kStreamBytes = std::size_t(8) << 20;
} // namespace

namespace depthcull {

using namespace detail;

namespace {

// A sprite's values in an element's ranges (the scene JSON,
// dc_scene_add_element): transform values within +-kMaxCoordinate keep
// every vertex a finite float (texels of at most kMaxImageSide, so
// |x| <= 3.3e13; 1e39 made Infinity), and colours in 0..1, since they go
// into the vertices as they are. NaN fails every comparison; bitwise &,
// so no branch per number.
constexpr double kMaxTransformValue = limits::kMaxCoordinate;
constexpr const char* kTransformRange = "is not a finite number within +-1e9 (kMaxCoordinate)";
constexpr const char* kColorRange = "is not in 0..1";

bool transform_value_ok(double v) { return std::abs(v) <= kMaxTransformValue; }
bool color_value_ok(float v) { return (v >= 0.0f) & (v <= 1.0f); }

bool sprite_in_range(const Sprite& s) {
    const auto& m = s.transform;
    const auto& c = s.color;
    // As ints: clang's -Wbitwise-instead-of-logical refuses & between bools.
    const int t = int(transform_value_ok(m[0])) & int(transform_value_ok(m[1])) & int(transform_value_ok(m[2])) &
                  int(transform_value_ok(m[3])) & int(transform_value_ok(m[4])) & int(transform_value_ok(m[5]));
    const int f = int(color_value_ok(c[0])) & int(color_value_ok(c[1])) & int(color_value_ok(c[2])) & int(color_value_ok(c[3]));
    return (t & f) != 0;
}

} // namespace

FrameStatus FrameAssembler::refuse(FrameStatus status, const char* field, const char* reason, std::int64_t item,
                                   std::optional<double> value) {
    problem_ = FrameProblem{};
    problem_.item = item;
    problem_.field = field;
    problem_.has_value = value.has_value();
    problem_.value = value.value_or(0);
    problem_.reason = reason;
    return status;
}

FrameStatus FrameAssembler::add_image(const SpriteImage& image, int* id) {
    const ImageAnalysis* a = image.analysis;
    constexpr FrameStatus bad = FrameStatus::bad_image;
    if (!id) return refuse(bad, "id", "is null");
    if (!a) return refuse(bad, "analysis", "is missing");
    if (image.texture < 0) return refuse(bad, "texture", "is negative", -1, double(image.texture));
    if (image.texture_width <= 0 || image.texture_height <= 0) return refuse(bad, "texture size", "is not positive");
    if (image.rect.empty()) return refuse(bad, "rect", "is empty");
    if (!ImageView{nullptr, image.texture_width, image.texture_height, 0}.contains(image.rect))
        return refuse(bad, "rect", "is outside the texture");
    // Its polygons are in texels of the texture: another rect's would be
    // drawn at that rect's place (a transparent rect's none at all), as
    // dc_scene_add_element refuses for an element.
    if (!(a->rect == image.rect)) return refuse(bad, "analysis", "is of another rect than the picture's");
    // A one-element scene for MeshBuilder, capturing texel-space polygons.
    Scene scene;
    scene.images.push_back({"", "", image.texture_width, image.texture_height});
    Element e;
    e.rect = image.rect;
    scene.elements.push_back(e);
    Picture p;
    p.texture = image.texture;
    p.rect = image.rect;
    std::fill(std::begin(p.boundary), std::end(p.boundary), kNone);
    std::fill(std::begin(p.opaque), std::end(p.opaque), kNone);
    const double iw = 1.0 / image.texture_width, ih = 1.0 / image.texture_height;
    // Vertices at the same texel position are one vertex (the same
    // position and texture coordinate, so drawn alike).
    auto to_template = [&](const TexelMesh& m, std::uint32_t* id) {
        Template t;
        std::map<std::pair<double, double>, std::uint32_t> index_of;
        for (std::uint32_t k : m.indices) {
            const Vec2 v = m.points[k];
            auto [it, fresh] = index_of.emplace(std::pair{v.x, v.y}, std::uint32_t(t.xy.size() / 2));
            if (fresh) {
                t.xy.push_back(v.x - image.rect.x);
                t.xy.push_back(v.y - image.rect.y);
                t.uv.push_back(float(v.x * iw));
                t.uv.push_back(float(v.y * ih));
            }
            t.indices.push_back(it->second);
        }
        // Whole groups of 4 vertices (emit's vector stores), padded with
        // copies of the last one, which no index names.
        while (t.xy.size() % 8 != 0) {
            t.xy.insert(t.xy.end(), {t.xy[t.xy.size() - 2], t.xy[t.xy.size() - 1]});
            t.uv.insert(t.uv.end(), {t.uv[t.uv.size() - 2], t.uv[t.uv.size() - 1]});
        }
        const std::size_t n = t.xy.size() / 2;
        t.vertex_count = std::uint32_t(n);
        t.index_count = std::uint32_t(t.indices.size());
        // Room for place_indices' last 4 (read, never used).
        t.indices.resize(t.indices.size() + 3);
        t.xxyy.resize(4 * n);
        for (std::size_t k = 0; k < n; ++k)
            t.xxyy[4 * k] = t.xxyy[4 * k + 1] = t.xy[2 * k], t.xxyy[4 * k + 2] = t.xxyy[4 * k + 3] = t.xy[2 * k + 1];
        // Vectors 0, 1, 3, 5, 7 of a group hold u0 | v0 | u1 v1 | u2 v2 | u3 v3
        // (the layout in emit_group).
        static constexpr int kLane[8] = {3, 4, 8, 9, 13, 14, 18, 19};
        t.uv_lanes.assign(n / 4 * 20, 0.0f);
        for (std::size_t g = 0; g < n / 4; ++g)
            for (int k = 0; k < 8; ++k) t.uv_lanes[20 * g + std::size_t(kLane[k])] = t.uv[8 * g + std::size_t(k)];
        *id = std::uint32_t(templates_.size());
        templates_.push_back(std::move(t));
    };
    auto vertex_count = [&](std::uint32_t id) { return id == kNone ? 0 : std::size_t(templates_[id].vertex_count); };
    auto index_count = [&](std::uint32_t id) { return id == kNone ? 0 : std::size_t(templates_[id].index_count); };
    Draw unused;
    p.has_boundary = !a->boundary.empty();
    p.has_opaque = !a->opaque.empty();
    std::size_t most_vertices = 8, most_indices = 12;
    for (int b = 0; b < kMarginBuckets; ++b) {
        const double margin = kTexelMargin * double(1 << b);
        // Boundary polygons with their texel skirt in the joined form
        // (texel_margin.cpp): a convex polygon's skirt is the polygon
        // dilated, which replaces it.
        if (p.has_boundary) {
            TexelMesh skirt, m;
            MeshBuilder skirted(scene, 0, 0, margin);
            skirted.capture(&skirt, true, true);
            skirted.add_texel_skirts(unused, 0, a->boundary, 0);
            for (std::size_t k = 0; k < a->boundary.size(); ++k) {
                if (k < skirted.dilated().size() && skirted.dilated()[k]) continue;
                const auto base = std::uint32_t(m.points.size());
                m.points.insert(m.points.end(), a->boundary[k].begin(), a->boundary[k].end());
                for (std::uint32_t t : triangulate_polygon(a->boundary[k])) m.indices.push_back(base + t);
            }
            const auto base = std::uint32_t(m.points.size());
            m.points.insert(m.points.end(), skirt.points.begin(), skirt.points.end());
            for (std::uint32_t t : skirt.indices) m.indices.push_back(base + t);
            to_template(m, &p.boundary[b]);
        }
        if (p.has_opaque) {
            TexelMesh opaque;
            MeshBuilder builder(scene, 0, 0, margin);
            builder.capture(&opaque, true);
            builder.add_opaque(unused, 0, Shape::analysis, a, 0);
            to_template(opaque, &p.opaque[b]);
            templates_[p.opaque[b]].opaque_key = image.texture * 4 + int(Blend::alpha);
        }
        // With the boundary template, or (edges that bleed) the quad.
        most_vertices = std::max(most_vertices, std::max(vertex_count(p.boundary[b]), std::size_t(4)) + vertex_count(p.opaque[b]));
        most_indices = std::max(most_indices, std::max(index_count(p.boundary[b]), std::size_t(6)) + index_count(p.opaque[b]));
    }
    p.has_opaque = index_count(p.opaque[0]) > 0;
    if (p.has_boundary) {
        // Without a skirt (transforms that snap exactly), as MeshBuilder draws them.
        TexelMesh m;
        MeshBuilder plain(scene, 0, 0, 0);
        plain.capture(&m, true);
        plain.add_boundary(unused, 0, Shape::analysis, a, 0);
        to_template(m, &p.plain);
        most_vertices = std::max(most_vertices, vertex_count(p.plain) + vertex_count(p.opaque[0]));
        most_indices = std::max(most_indices, index_count(p.plain) + index_count(p.opaque[0]));
        p.boundary_inside = true;
        for (const Polygon& poly : a->boundary)
            for (const Vec2& v : poly)
                if (v.x < image.rect.x || v.y < image.rect.y || v.x > double(image.rect.x) + image.rect.w ||
                    v.y > double(image.rect.y) + image.rect.h)
                    p.boundary_inside = false;
    }
    {
        const Polygon r = rect_polygon(image.rect);
        TexelMesh quad{{r.begin(), r.end()}, {0, 1, 2, 0, 2, 3}};
        to_template(quad, &p.quad);
        templates_[p.quad].opaque_key = image.texture * 4 + int(Blend::opaque);
    }
    p.bleeding_edges = a->bleeding_edges;
    p.opaque_covers_all = a->stats.nontransparent_texels > 0 && a->stats.opaque_covered_texels == a->stats.nontransparent_texels;
    // The box that holds whatever the sprite draws: its rect (skirts are
    // clipped to it).
    p.bx0 = 0, p.by0 = 0, p.bx1 = image.rect.w, p.by1 = image.rect.h;
    if (p.has_boundary && p.boundary_inside) {
        p.bx0 = p.by0 = INFINITY, p.bx1 = p.by1 = -INFINITY;
        for (std::uint32_t id : p.boundary) {
            const std::vector<double>& xy = templates_[id].xy;
            for (std::size_t k = 0; k + 1 < xy.size(); k += 2) {
                p.bx0 = std::min(p.bx0, xy[k]), p.bx1 = std::max(p.bx1, xy[k]);
                p.by0 = std::min(p.by0, xy[k + 1]), p.by1 = std::max(p.by1, xy[k + 1]);
            }
        }
    }
    max_vertices_ = std::max(max_vertices_, most_vertices);
    max_indices_ = std::max(max_indices_, most_indices);
    max_texture_ = std::max(max_texture_, image.texture);
    *id = int(images_.size());
    images_.push_back(std::move(p));
    return FrameStatus::ok;
}

FrameStatus FrameAssembler::add_animation(std::span<const int> images, int* id) {
    if (!id) return refuse(FrameStatus::bad_image, "id", "is null");
    if (images.empty()) return refuse(FrameStatus::bad_image, "frames", "are none: an animation shows at least one picture");
    for (std::size_t k = 0; k < images.size(); ++k)
        if (images[k] < 0 || std::size_t(images[k]) >= images_.size())
            return refuse(FrameStatus::bad_image, "image", "is not an add_image id", std::int64_t(k), double(images[k]));
    *id = int(animations_.size());
    animations_.emplace_back(images.begin(), images.end());
    return FrameStatus::ok;
}

FrameStatus FrameAssembler::reserve(std::size_t sprites, AssembledFrame* out) {
    // Checked before any allocation: a count past every frame's size would
    // otherwise overflow the products below (a length_error) or ask for
    // terabytes.
    if (sprites > std::size_t(kMaxDepthLevels))
        return refuse(FrameStatus::too_many_sprites, "sprites", "is more than a frame holds (one depth level each, kMaxDepthLevels)", -1,
                      double(sprites));
    plan_.reserve(sprites);
    batch_key_.reserve(sprites);
    batch_count_.reserve(sprites);
    const std::size_t keys = std::size_t(max_texture_ + 1) * 4;
    last_batch_of_key_.reserve(keys);
    key_count_.reserve(keys);
    key_nearest_.reserve(keys);
    key_order_.reserve(keys);
    cell_top_.reserve(std::size_t(std::max(options_.max_cells, 1)) + 3);
    ranges_.reserve(16);
    point_batch_.reserve(17);
    if (out) {
        out->vertices.reserve(sprites * max_vertices_ * kVertexFloats);
        out->indices.reserve(sprites * max_indices_);
        out->draws.reserve(2 * sprites + 1);
        out->points.reserve(16);
    }
    return FrameStatus::ok;
}

struct FrameAssembler::SpriteShape {
    const Picture* picture;
    std::int32_t key;     // texture * 4 + blend
    std::int8_t boundary; // 0 none, 1 analysis, 2 rect
    std::int8_t opaque;   // 0 none, 1 analysis, 2 rect
    std::int8_t margin;   // the templates' bucket
    bool blended;
};

inline FrameStatus FrameAssembler::plan_sprite(const Sprite& s, SpriteShape& p) const {
    int picture = s.image;
    if (s.animation >= 0) {
        if (std::size_t(s.animation) >= animations_.size()) return FrameStatus::bad_sprite;
        const std::vector<int>& frames = animations_[std::size_t(s.animation)];
        const int n = int(frames.size());
        picture = frames[std::size_t(((s.frame % n) + n) % n)];
    }
    if (picture < 0 || std::size_t(picture) >= images_.size() || !sprite_in_range(s) || int(s.blend) < 0 || int(s.blend) > 3)
        return FrameStatus::bad_sprite;
    const Picture& pic = images_[std::size_t(picture)];
    p.picture = &pic;
    p.key = pic.texture * 4 + int(s.blend);
    p.opaque = 0;
    p.margin = 0;
    p.blended = false;
    // shapes.cpp's rules, per sprite.
    if (s.blend == Blend::opaque || s.blend == Blend::multiply) p.boundary = 2;
    else if (s.color[3] <= 0.0f || !pic.has_boundary) p.boundary = 0;
    else p.boundary = pic.boundary_inside ? 1 : 2;
    if (p.boundary == 0) return FrameStatus::ok;
    // Frames are for a plain renderer (texel skirts, no coverage skirts):
    // a sprite GL snaps whose picture's edges bleed draws its whole rect,
    // as reconstruction's rect_edges does for such an element.
    if (p.boundary == 1 && needs_rect_edges(pic.bleeding_edges, s.transform)) p.boundary = 2;
    if (options_.opaque_pass) {
        if (s.blend == Blend::opaque) p.opaque = 2;
        else if (s.blend == Blend::alpha && s.color[3] == 1.0f && pic.has_opaque) p.opaque = 1;
    }
    p.blended = !(options_.opaque_pass && s.blend == Blend::opaque);
    // MeshBuilder::element_texel_margin: below a scale of 1/8 the margin
    // grows to 1/256 pixel along the most shrunk direction, at most half a
    // texel. The templates' margin is the next power of two up: a wider
    // skirt still lies outside every polygon (its templates keep 3 margins
    // clear as MeshBuilder does), and the opaque polygons, pulled in
    // further, leave a strip the blend draw then covers, so the sprite
    // blends even where its opaque polygons cover all it shows.
    const auto& t = s.transform;
    const double sum = t[0] * t[0] + t[1] * t[1] + t[2] * t[2] + t[3] * t[3], det = t[0] * t[3] - t[1] * t[2];
    if (64 * det * det < sum) { // else the smallest singular value, >= |det| / sqrt(sum), is >= 1/8
        const double smallest = std::sqrt(std::max(0.0, (sum - std::sqrt(std::max(0.0, sum * sum - 4 * det * det))) / 2));
        if (smallest > 0) {
            const double margin = std::min(0.5, (1.0 / 256) / smallest);
            while (p.margin + 1 < kMarginBuckets && kTexelMargin * double(1 << p.margin) < margin) ++p.margin;
        }
    }
    if (p.opaque == 1 && options_.filter == Filter::nearest && pic.opaque_covers_all && p.boundary == 1 && p.margin == 0)
        p.blended = false;
    return FrameStatus::ok;
}

// plan_sprite's checks again, one by one, for the field to name.
FrameProblem FrameAssembler::sprite_problem(const Sprite& s) const {
    FrameProblem p;
    auto set = [&](const char* field, const char* reason, int component, double value) {
        p.field = field, p.reason = reason, p.component = component, p.has_value = true, p.value = value;
        return p;
    };
    int picture = s.image;
    if (s.animation >= 0) {
        if (std::size_t(s.animation) >= animations_.size()) return set("animation", "is not an add_animation id", -1, s.animation);
        const std::vector<int>& frames = animations_[std::size_t(s.animation)];
        const int n = int(frames.size());
        picture = frames[std::size_t(((s.frame % n) + n) % n)];
    }
    if (picture < 0 || std::size_t(picture) >= images_.size()) return set("image", "is not an add_image id", -1, picture);
    for (int k = 0; k < 6; ++k)
        if (!transform_value_ok(s.transform[std::size_t(k)])) return set("transform", kTransformRange, k, s.transform[std::size_t(k)]);
    for (int k = 0; k < 4; ++k)
        if (!color_value_ok(s.color[std::size_t(k)])) return set("color", kColorRange, k, s.color[std::size_t(k)]);
    return set("blend", "is not a Blend", -1, int(s.blend));
}

namespace {

// A template's vertices transformed for one sprite, kVertexFloats each
// (x y z u v r g b a): apply()'s operations, so the same roundings.
void emit_scalar(const double* xy, const float* uv, std::size_t n, const Sprite& s, float z, float* v) {
    // Locals: the stores through v (floats) could otherwise alias the
    // sprite's colour, reloaded for every vertex.
    const double a = s.transform[0], b = s.transform[1], c = s.transform[2], d = s.transform[3], e = s.transform[4],
                 f = s.transform[5];
    const float r = s.color[0], g = s.color[1], bl = s.color[2], al = s.color[3];
    for (std::size_t k = 0; k < n; ++k, v += kVertexFloats) {
        const double x = xy[2 * k], y = xy[2 * k + 1];
        v[0] = float(a * x + c * y + e), v[1] = float(b * x + d * y + f), v[2] = z, v[3] = uv[2 * k], v[4] = uv[2 * k + 1];
        v[5] = r, v[6] = g, v[7] = bl, v[8] = al;
    }
}

#if DEPTHCULL_STREAM_VERTICES
// The same with SSE2, a group of 4 vertices (36 floats, 9 aligned vectors)
// at a time. Per vertex one multiply of {x, x} by {a, b} and of {y, y} by
// {c, d}, added, plus {e, f}: each lane apply()'s a*x + c*y + e in its
// order (no FMA on baseline x86-64), so the same floats. The lanes that
// hold no x or y are per sprite (z, colour) or per template (uv, in
// Template::uv_lanes), or-ed in: no shuffles but one shift per vertex.
//
// Streaming stores for frames too big for the caches: their vertices
// are written once and read by the upload, so they bypass the cache
// rather than read each line in first (half the memory traffic; a frame
// of 100,000 sprites writes 40 MB).
template <bool kStream>
inline void put(float* p, __m128 x) {
    if constexpr (kStream) _mm_stream_ps(p, x);
    else _mm_store_ps(p, x);
}

template <bool kStream>
void emit_groups(const double* xxyy, const float* uv_lanes, std::size_t groups, const Sprite& s, float z, float* v) {
    const __m128d ab = _mm_setr_pd(s.transform[0], s.transform[1]), cd = _mm_setr_pd(s.transform[2], s.transform[3]),
                  ef = _mm_setr_pd(s.transform[4], s.transform[5]);
    const float r = s.color[0], g = s.color[1], b = s.color[2], al = s.color[3];
    // Vertices x y z u v r g b a; a group's vectors:
    //   x0 y0 z u0 | v0 r g b | al x1 y1 z | u1 v1 r g | b al x2 y2 |
    //   z u2 v2 r | g b al x3 | y3 z u3 v3 | r g b al
    const __m128 s0 = _mm_setr_ps(0, 0, z, 0), s1 = _mm_setr_ps(0, r, g, b), s2 = _mm_setr_ps(al, 0, 0, z),
                 s3 = _mm_setr_ps(0, 0, r, g), s4 = _mm_setr_ps(b, al, 0, 0), s5 = _mm_setr_ps(z, 0, 0, r),
                 s6 = _mm_setr_ps(g, b, al, 0), s7 = _mm_setr_ps(0, z, 0, 0), s8 = _mm_setr_ps(r, g, b, al);
    auto shift = [](__m128 x, auto bytes) { // lanes up (bytes > 0) or down
        if constexpr (decltype(bytes)::value > 0) return _mm_castsi128_ps(_mm_slli_si128(_mm_castps_si128(x), decltype(bytes)::value));
        else return _mm_castsi128_ps(_mm_srli_si128(_mm_castps_si128(x), -decltype(bytes)::value));
    };
    for (std::size_t k = 0; k < groups; ++k, xxyy += 16, uv_lanes += 20, v += 4 * kVertexFloats) {
        // {x, y, 0, 0} of vertex j
        auto position = [&](int j) {
            const __m128d x = _mm_mul_pd(_mm_loadu_pd(xxyy + 4 * j), ab), y = _mm_mul_pd(_mm_loadu_pd(xxyy + 4 * j + 2), cd);
            return _mm_cvtpd_ps(_mm_add_pd(_mm_add_pd(x, y), ef));
        };
        const __m128 p0 = position(0), p1 = position(1), p2 = position(2), p3 = position(3);
        put<kStream>(v + 0, _mm_or_ps(_mm_or_ps(s0, _mm_loadu_ps(uv_lanes)), p0));
        put<kStream>(v + 4, _mm_or_ps(s1, _mm_loadu_ps(uv_lanes + 4)));
        put<kStream>(v + 8, _mm_or_ps(s2, shift(p1, std::integral_constant<int, 4>{})));
        put<kStream>(v + 12, _mm_or_ps(s3, _mm_loadu_ps(uv_lanes + 8)));
        put<kStream>(v + 16, _mm_or_ps(s4, shift(p2, std::integral_constant<int, 8>{})));
        put<kStream>(v + 20, _mm_or_ps(s5, _mm_loadu_ps(uv_lanes + 12)));
        put<kStream>(v + 24, _mm_or_ps(s6, shift(p3, std::integral_constant<int, 12>{})));
        put<kStream>(v + 28, _mm_or_ps(_mm_or_ps(s7, _mm_loadu_ps(uv_lanes + 16)), shift(p3, std::integral_constant<int, -4>{})));
        put<kStream>(v + 32, s8);
    }
}
#endif

// A template's indices plus a sprite's first vertex, `count` of them at
// `to`. With SSE2, 4 at a time, the last 4 ending at `count` (rewriting a
// few, the same): no loop tail. Templates hold 3 indices more than they
// use, so reading 4 at a time stays inside.
inline void place_indices(const std::uint32_t* from, std::uint32_t count, std::uint32_t base, std::uint32_t* to) {
#if DEPTHCULL_STREAM_VERTICES
    if (count >= 4) {
        const __m128i add = _mm_set1_epi32(int(base));
        std::uint32_t k = 0;
        for (; k + 4 <= count; k += 4)
            _mm_storeu_si128(reinterpret_cast<__m128i*>(to + k),
                             _mm_add_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(from + k)), add));
        if (k < count)
            _mm_storeu_si128(reinterpret_cast<__m128i*>(to + count - 4),
                             _mm_add_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(from + count - 4)), add));
        return;
    }
#endif
    for (std::uint32_t k = 0; k < count; ++k) to[k] = base + from[k];
}

#if DEPTHCULL_SSE2_GRID
// SSE2 has no pmaxsd.
inline __m128i max_epi32(__m128i a, __m128i b) {
    const __m128i greater = _mm_cmpgt_epi32(a, b);
    return _mm_or_si128(_mm_and_si128(greater, a), _mm_andnot_si128(greater, b));
}
#endif

} // namespace

// One pass over the sprites in painter's order plans each, writes its
// vertices (sprites and vertices read and written in sequence) and finds
// its blend batch; the draws then only place indices, each sprite's at its
// draw's cursor (a counting sort by draw), in two more passes.
FrameStatus FrameAssembler::run(const Viewport& bounds, AssembledFrame* out) {
    const std::size_t n = ranges_.empty() ? 0 : ranges_.back().end;
    plan_.resize(n);
    // The last frame's size tells whether this one outgrows the caches
    // (the stores differ, the vertices written do not).
    // (Used only with SSE2: the WebAssembly build has it unused.)
    [[maybe_unused]] const bool stream = out->vertices.size() * sizeof(float) > kStreamBytes;
    // The vertices are written at a cursor into the whole capacity
    // (uninitialized, so this stores nothing), cut to size at the end: no
    // resize per template.
    auto& vertices = out->vertices;
    vertices.clear();
    vertices.resize(vertices.capacity());
    std::size_t vertex_end = 0; // vertices written
    auto fail = [&](FrameStatus st) {
#if DEPTHCULL_STREAM_VERTICES
        _mm_sfence();
#endif
        out->vertices.clear();
        out->stats = {};
        return st;
    };
    out->indices.clear();
    out->draws.clear();
    out->points.clear();
    out->stats = {};
    out->stats.sprites = std::int64_t(n);
    out->depth_test = options_.opaque_pass;
    out->depth_denominator = denominator_;
    const std::size_t keys = std::size_t(max_texture_ + 1) * 4;
    key_count_.assign(keys, 0);    // opaque indices per key
    key_nearest_.assign(keys, -1); // per key its nearest opaque sprite
    batch_key_.clear();
    batch_count_.clear(); // blend indices per batch
    point_batch_.clear();
    std::size_t opaque_indices = 0, blend_indices = 0;

    // The overlap grid over `bounds`.
    double cell = options_.cell_size > 0 && std::isfinite(options_.cell_size) ? options_.cell_size : 64;
    const double w = std::max(bounds.width, 1), h = std::max(bounds.height, 1);
    const double max_cells = std::max(options_.max_cells, 1);
    while (std::ceil(w / cell) * std::ceil(h / cell) > max_cells) cell *= 2;
    const int cols = int(std::ceil(w / cell)), rows = int(std::ceil(h / cell));
    const double inv = 1 / cell;
    // int(c) is floor(c) for c >= 0, and c < 0 clamps to 0 anyway. No
    // branch (minsd, maxsd). NaN (a huge transform's inf - inf) gives the
    // first cell as the low end of a box, the last as the high end: the
    // whole grid.
    auto low_cell = [](double c, int n) { return int(std::max(0.0, std::min(c, double(n - 1)))); };
    auto high_cell = [](double c, int n) { return int(std::min(double(n - 1), std::max(c, 0.0))); };

    // depth_z with the reciprocal: within a double rounding of its
    // quotient, so at most a float ulp (2^-24 below 1) off, while levels lie
    // 1/D >= 2^-23 apart: the order of every z, static ones included, holds.
    const double inverse = 1 / double(denominator_);
    auto z_of = [&](std::int64_t level, bool opaque) { return float(double(2 * level + (opaque ? 2 : 1)) * inverse); };
    auto emit = [&](const Template& t, const Sprite& s, float z, float* v) {
        const std::size_t count = t.vertex_count;
#if DEPTHCULL_STREAM_VERTICES
        // Templates hold whole groups of 4 vertices (to_template pads
        // them), so every group starts 16-byte aligned.
        if (reinterpret_cast<std::uintptr_t>(v) % 16 == 0) {
            if (stream) emit_groups<true>(t.xxyy.data(), t.uv_lanes.data(), count / 4, s, z, v);
            else emit_groups<false>(t.xxyy.data(), t.uv_lanes.data(), count / 4, s, z, v);
            return;
        }
#endif
        emit_scalar(t.xy.data(), t.uv.data(), count, s, z, v);
    };
    for (const Range& range : ranges_) {
        // Each point batches on its own (its draws go between other static draws).
        point_batch_.push_back(std::uint32_t(batch_key_.size()));
        // 3 cells more: a box's rows are read 4 cells at a time.
        cell_top_.assign(std::size_t(cols) * std::size_t(rows) + 3, -1);
        last_batch_of_key_.assign(keys, -1);
        std::int32_t all_top = -1, wide_top = -1;
        for (std::size_t i = range.first; i < range.end; ++i) {
            const Sprite& s = range.sprites[i - range.first];
            const std::int64_t level = range.first_level + std::int64_t(i - range.first);
            SpriteShape p;
            if (FrameStatus st = plan_sprite(s, p); st != FrameStatus::ok) {
                problem_ = sprite_problem(s);
                problem_.point = std::int64_t(&range - ranges_.data()); // assemble() makes it -1
                problem_.item = std::int64_t(i - range.first);
                return fail(st);
            }
            const Picture& pic = *p.picture;
            Plan& q = plan_[i];
            q.base = std::uint32_t(vertex_end);
            q.batch = -1;
            q.opaque_template = p.opaque == 0 ? kNone : p.opaque == 2 ? pic.quad : pic.opaque[p.margin];
            q.blend_template = !p.blended            ? kNone
                               : p.boundary == 2     ? pic.quad
                               : s.blend != Blend::opaque && !snaps_exactly(s.transform) ? pic.boundary[p.margin]
                                                                                         : pic.plain;
            const Template* opaque = q.opaque_template == kNone ? nullptr : &templates_[q.opaque_template];
            const Template* blend = q.blend_template == kNone ? nullptr : &templates_[q.blend_template];
            const std::size_t opaque_vertices = opaque ? opaque->vertex_count : 0;
            const std::size_t count = opaque_vertices + (blend ? blend->vertex_count : 0);
            if ((vertex_end + count) * kVertexFloats > vertices.size()) { // grows (until warmed up)
                vertices.resize(vertex_end * kVertexFloats);
                vertices.resize((vertex_end + count) * kVertexFloats);
                vertices.resize(vertices.capacity());
            }
            float* v = vertices.data() + vertex_end * kVertexFloats;
            vertex_end += count;
            if (opaque) {
                emit(*opaque, s, z_of(level, true), v);
                const auto key = std::size_t(opaque->opaque_key);
                key_count_[key] += std::int32_t(opaque->index_count);
                key_nearest_[key] = std::int64_t(i); // levels grow with i
                opaque_indices += opaque->index_count;
            }
            if (!blend) continue;
            emit(*blend, s, z_of(level, false), v + opaque_vertices * kVertexFloats);
            // The screen box of what it draws: its centre's image plus the
            // half extents' absolute images, and a pixel for GL's snapping
            // (and rounding): cells are conservative.
            double x0 = pic.bx0, y0 = pic.by0, x1 = pic.bx1, y1 = pic.by1;
            if (p.boundary == 2) x0 = 0, y0 = 0, x1 = pic.rect.w, y1 = pic.rect.h;
            const auto& m = s.transform;
            const double hx = (x1 - x0) / 2, hy = (y1 - y0) / 2;
            const Vec2 centre = apply(m, {x0 + hx, y0 + hy});
            const double ex = std::abs(m[0]) * hx + std::abs(m[2]) * hy + 1, ey = std::abs(m[1]) * hx + std::abs(m[3]) * hy + 1;
            const int cx0 = low_cell((centre.x - ex - bounds.x) * inv, cols);
            const int cx1 = high_cell((centre.x + ex - bounds.x) * inv, cols);
            const int cy0 = low_cell((centre.y - ey - bounds.y) * inv, rows);
            const int cy1 = high_cell((centre.y + ey - bounds.y) * inv, rows);
            const bool wide = std::int64_t(cx1 - cx0 + 1) * (cy1 - cy0 + 1) > options_.cell_budget;
            std::int32_t top = all_top;
#if DEPTHCULL_SSE2_GRID
            // Boxes of up to 4 x 4 cells (most sprites) without a branch
            // per cell: 4 rows of 4 cells, lanes past the box masked (-1
            // read, the cell's own value written back), rows past it
            // repeating its last.
            const bool small = !wide && cx1 - cx0 < 4 && cy1 - cy0 < 4;
            std::int32_t* box[4];
            __m128i in_box = _mm_setzero_si128();
            if (small) {
                in_box = _mm_cmplt_epi32(_mm_setr_epi32(0, 1, 2, 3), _mm_set1_epi32(cx1 - cx0 + 1));
                const __m128i outside = _mm_andnot_si128(in_box, _mm_set1_epi32(-1));
                __m128i row[4];
                for (int k = 0; k < 4; ++k) {
                    box[k] = cell_top_.data() + std::size_t(std::min(cy0 + k, cy1)) * std::size_t(cols) + std::size_t(cx0);
                    row[k] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(box[k]));
                }
                __m128i most = _mm_or_si128(max_epi32(max_epi32(row[0], row[1]), max_epi32(row[2], row[3])), outside);
                most = max_epi32(most, _mm_set1_epi32(wide_top));
                most = max_epi32(most, _mm_shuffle_epi32(most, _MM_SHUFFLE(1, 0, 3, 2)));
                most = max_epi32(most, _mm_shuffle_epi32(most, _MM_SHUFFLE(2, 3, 0, 1)));
                top = _mm_cvtsi128_si32(most);
            } else
#endif
            if (!wide) {
                top = wide_top;
                for (int cy = cy0; cy <= cy1; ++cy) {
                    const std::int32_t* row = cell_top_.data() + std::size_t(cy) * std::size_t(cols);
                    for (int cx = cx0; cx <= cx1; ++cx) top = std::max(top, row[cx]);
                }
            } else {
                ++out->stats.over_budget;
            }
            // The earliest batch this sprite may join: after every batch of
            // a sprite it may overlap, or that very batch when it is its own
            // key (a batch draws its sprites in painter's order).
            const std::int32_t lowest = top < 0 ? 0 : batch_key_[std::size_t(top)] == p.key ? top : top + 1;
            std::int32_t b = last_batch_of_key_[std::size_t(p.key)];
            if (b < lowest) {
                b = std::int32_t(batch_key_.size());
                batch_key_.push_back(p.key);
                batch_count_.push_back(0);
                last_batch_of_key_[std::size_t(p.key)] = b;
            }
            q.batch = b;
            batch_count_[std::size_t(b)] += std::int32_t(blend->index_count);
            blend_indices += blend->index_count;
            // b is at least every batch its cells hold (at least top).
            all_top = std::max(all_top, b);
#if DEPTHCULL_SSE2_GRID
            if (small) {
                const __m128i batch = _mm_and_si128(in_box, _mm_set1_epi32(b));
                for (std::int32_t* row : box) {
                    const __m128i old = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row));
                    _mm_storeu_si128(reinterpret_cast<__m128i*>(row), _mm_or_si128(batch, _mm_andnot_si128(in_box, old)));
                }
            } else
#endif
            if (wide) wide_top = std::max(wide_top, b);
            else
                for (int cy = cy0; cy <= cy1; ++cy) {
                    std::int32_t* row = cell_top_.data() + std::size_t(cy) * std::size_t(cols);
                    for (int cx = cx0; cx <= cx1; ++cx) row[cx] = b;
                }
        }
    }
    point_batch_.push_back(std::uint32_t(batch_key_.size()));
#if DEPTHCULL_STREAM_VERTICES
    _mm_sfence(); // streaming stores are ordered before whatever reads the frame
#endif
    vertices.resize(vertex_end * kVertexFloats);
    if (opaque_indices + blend_indices > std::size_t(INT32_MAX)) // draws count indices in 32 bits
        return fail(refuse(FrameStatus::too_many_sprites, "sprites", "draw more than 2^31 - 1 indices", -1, double(n)));
    out->indices.resize(opaque_indices + blend_indices);
    std::uint32_t* indices = out->indices.data();
    auto place = [&](const Template& t, std::uint32_t base, std::int32_t& cursor) {
        place_indices(t.indices.data(), t.index_count, base, indices + cursor);
        cursor += std::int32_t(t.index_count);
    };

    // The opaque pass, front to back: keys by their nearest sprite,
    // sprites nearest first (append_opaque_draws' order). Levels grow with
    // the flat index. key_count_ becomes the end of each key's indices,
    // filled backwards as the sprites go forwards.
    if (opaque_indices) {
        key_order_.clear();
        for (std::size_t k = 0; k < keys; ++k)
            if (key_nearest_[k] >= 0) key_order_.push_back(std::int32_t(k));
        std::sort(key_order_.begin(), key_order_.end(),
                  [&](std::int32_t x, std::int32_t y) { return key_nearest_[std::size_t(x)] > key_nearest_[std::size_t(y)]; });
        std::int32_t at = 0;
        for (std::int32_t k : key_order_) {
            const std::int32_t count = key_count_[std::size_t(k)];
            out->draws.push_back({k / 4, Pass::opaque, Blend(k % 4), std::uint32_t(at), std::uint32_t(count)});
            at += count;
            key_count_[std::size_t(k)] = at;
        }
    }
    out->opaque_draws = out->draws.size();

    // The blend pass: each point's batches in order, sprites in painter's
    // order within one. batch_count_ becomes each batch's cursor.
    std::int32_t at = std::int32_t(opaque_indices);
    for (std::size_t r = 0; r < ranges_.size(); ++r) {
        FramePoint point;
        point.static_draw = ranges_[r].static_draw;
        point.first_draw = std::uint32_t(out->draws.size());
        for (std::uint32_t b = point_batch_[r]; b < point_batch_[r + 1]; ++b) {
            const std::int32_t key = batch_key_[b], count = batch_count_[b];
            out->draws.push_back({key / 4, Pass::blend, Blend(key % 4), std::uint32_t(at), std::uint32_t(count)});
            batch_count_[b] = at;
            at += count;
        }
        point.end_draw = std::uint32_t(out->draws.size());
        out->points.push_back(point);
    }
    // One pass places both: blend indices forwards from each batch's
    // cursor, opaque ones backwards from each key's end.
    for (std::size_t i = 0; i < n; ++i) {
        const Plan& p = plan_[i];
        std::uint32_t base = p.base;
        if (p.opaque_template != kNone) {
            const Template& t = templates_[p.opaque_template];
            std::int32_t& end = key_count_[std::size_t(t.opaque_key)];
            end -= std::int32_t(t.index_count);
            std::int32_t cursor = end;
            place(t, base, cursor);
            base += t.vertex_count;
        }
        if (p.blend_template != kNone) place(templates_[p.blend_template], base, batch_count_[std::size_t(p.batch)]);
    }
    out->stats.draw_calls = std::int64_t(out->draws.size());
    out->stats.opaque_draws = std::int64_t(out->opaque_draws);
    out->stats.blend_batches = out->stats.draw_calls - out->stats.opaque_draws;
    out->stats.triangles = std::int64_t(out->indices.size() / 3);
    return FrameStatus::ok;
}

FrameStatus FrameAssembler::assemble(std::span<const Sprite> sprites, const Viewport& bounds, AssembledFrame* out) {
    if (!out) return refuse(FrameStatus::bad_sprite, "out", "is null");
    if (sprites.size() > std::size_t(kMaxDepthLevels))
        return refuse(FrameStatus::too_many_sprites, "sprites", "are more than the depth levels (kMaxDepthLevels)", -1, double(sprites.size()));
    denominator_ = depth_denominator(std::int64_t(sprites.size()));
    ranges_.clear();
    ranges_.push_back({0, 0, std::uint32_t(sprites.size()), sprites.data(), 0});
    const FrameStatus st = run(bounds, out);
    if (st != FrameStatus::ok) problem_.point = -1; // one list, no insertion points
    return st;
}

FrameStatus FrameAssembler::assemble_at(const SceneMeshes& static_meshes, std::span<const std::span<const Sprite>> sprites,
                                        const Viewport& bounds, AssembledFrame* out) {
    if (!out) return refuse(FrameStatus::bad_meshes, "out", "is null");
    if (sprites.size() > static_meshes.insertion_points.size())
        return refuse(FrameStatus::bad_meshes, "sprite lists", "are more than the static meshes' insertion points", -1, double(sprites.size()));
    if (static_meshes.depth_denominator < 2) return refuse(FrameStatus::bad_meshes, "static meshes", "have no depth values");
    ranges_.clear();
    std::uint32_t at = 0;
    for (std::size_t k = 0; k < sprites.size(); ++k) {
        const InsertionPoint& point = static_meshes.insertion_points[k];
        if (std::int64_t(sprites[k].size()) > point.levels) {
            refuse(FrameStatus::too_many_sprites, "sprites", "are more than the point's reserved levels", -1, double(sprites[k].size()));
            problem_.point = std::int64_t(k);
            return FrameStatus::too_many_sprites;
        }
        ranges_.push_back({point.blend_draw, at, at + std::uint32_t(sprites[k].size()), sprites[k].data(), point.first_level});
        at += std::uint32_t(sprites[k].size());
    }
    denominator_ = static_meshes.depth_denominator;
    const FrameStatus st = run(bounds, out);
    out->depth_test = static_meshes.depth_test;
    return st;
}

} // namespace depthcull
