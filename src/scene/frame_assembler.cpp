// FrameAssembler (depthcull/frame.h): moving sprites depth-culled every
// frame. Each sprite follows the rules reconstruction gives an element
// (shapes.cpp), and its vertices are exactly the ones MeshBuilder would make
// for it (the same texel-space polygons, skirts and pulled-in opaque
// polygons, transformed the same way), so a frame draws pixel for pixel
// like overpaint in a plain renderer (texel_margin.cpp says why).
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
#include <map>

#include "depthcull/frame.h"
#include "scene/internal.h"
#include "scene/placement.h"

namespace depthcull {

using namespace detail;

namespace {

bool finite_sprite(const Sprite& s) {
    for (double v : s.transform)
        if (!std::isfinite(v)) return false;
    for (float c : s.color)
        if (!std::isfinite(c)) return false;
    return true;
}

} // namespace

FrameStatus FrameAssembler::add_image(const SpriteImage& image, int* id) {
    const ImageAnalysis* a = image.analysis;
    if (!id || !a || image.texture < 0 || image.rect.empty() || image.texture_width <= 0 || image.texture_height <= 0 ||
        !ImageView{nullptr, image.texture_width, image.texture_height, 0}.contains(image.rect))
        return FrameStatus::bad_image;
    // A one-element scene for MeshBuilder, capturing texel-space polygons.
    Scene scene;
    scene.images.push_back({"", "", image.texture_width, image.texture_height});
    Element e;
    e.rect = image.rect;
    scene.elements.push_back(e);
    Picture p;
    p.texture = image.texture;
    p.rect = image.rect;
    const double iw = 1.0 / image.texture_width, ih = 1.0 / image.texture_height;
    // Vertices at the same texel position are one vertex (the same
    // position and texture coordinate, so drawn alike): the polygons'
    // vertices first, so a sprite drawn without its skirt transforms only
    // those (plain_vertices).
    auto to_template = [&](const TexelMesh& m, std::size_t plain_indices, Template& t) {
        std::map<std::pair<double, double>, std::uint32_t> index_of;
        std::vector<std::uint32_t> remap(m.points.size());
        auto weld = [&](std::uint32_t k) {
            const Vec2 v = m.points[k];
            auto [it, fresh] = index_of.emplace(std::pair{v.x, v.y}, std::uint32_t(t.xy.size() / 2));
            if (fresh) {
                t.xy.push_back(v.x - image.rect.x);
                t.xy.push_back(v.y - image.rect.y);
                t.uv.push_back(float(v.x * iw));
                t.uv.push_back(float(v.y * ih));
            }
            return it->second;
        };
        for (std::size_t k = 0; k < m.indices.size(); ++k) {
            if (k == plain_indices) t.plain_vertices = std::uint32_t(t.xy.size() / 2);
            t.indices.push_back(weld(m.indices[k]));
        }
        if (plain_indices >= m.indices.size()) t.plain_vertices = std::uint32_t(t.xy.size() / 2);
        t.skirt_start = std::uint32_t(plain_indices);
    };
    Draw unused;
    p.has_boundary = !a->boundary.empty();
    p.has_opaque = !a->opaque.empty();
    std::size_t most_vertices = 8, most_indices = 12;
    for (int b = 0; b < kMarginBuckets; ++b) {
        const double margin = kTexelMargin * double(1 << b);
        // Boundary polygons, then their texel skirt in the joined form
        // (left out for transforms that snap exactly, as MeshBuilder does).
        if (p.has_boundary) {
            TexelMesh m;
            MeshBuilder plain(scene, 0, 0, 0);
            plain.capture(&m, true);
            plain.add_boundary(unused, 0, Shape::analysis, a, 0);
            const std::size_t skirt_start = m.indices.size();
            MeshBuilder skirted(scene, 0, 0, margin);
            skirted.capture(&m, true, true);
            skirted.add_texel_skirts(unused, 0, a->boundary, 0);
            to_template(m, skirt_start, p.boundary[b]);
        }
        if (p.has_opaque) {
            TexelMesh opaque;
            MeshBuilder builder(scene, 0, 0, margin);
            builder.capture(&opaque, true);
            builder.add_opaque(unused, 0, Shape::analysis, a, 0);
            to_template(opaque, opaque.indices.size(), p.opaque[b]);
        }
        most_vertices = std::max(most_vertices, p.boundary[b].xy.size() / 2 + p.opaque[b].xy.size() / 2);
        most_indices = std::max(most_indices, p.boundary[b].indices.size() + p.opaque[b].indices.size());
    }
    p.has_opaque = !p.opaque[0].indices.empty();
    if (p.has_boundary) {
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
        to_template(quad, 6, p.quad);
    }
    p.bleeding_edges = a->bleeding_edges;
    p.opaque_covers_all = a->stats.nontransparent_texels > 0 && a->stats.opaque_covered_texels == a->stats.nontransparent_texels;
    // The box that holds whatever the sprite draws: its rect (skirts are
    // clipped to it).
    p.bx0 = 0, p.by0 = 0, p.bx1 = image.rect.w, p.by1 = image.rect.h;
    if (p.has_boundary && p.boundary_inside) {
        p.bx0 = p.by0 = INFINITY, p.bx1 = p.by1 = -INFINITY;
        for (const Template& t : p.boundary)
            for (std::size_t k = 0; k + 1 < t.xy.size(); k += 2) {
                p.bx0 = std::min(p.bx0, t.xy[k]), p.bx1 = std::max(p.bx1, t.xy[k]);
                p.by0 = std::min(p.by0, t.xy[k + 1]), p.by1 = std::max(p.by1, t.xy[k + 1]);
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
    if (!id || images.empty()) return FrameStatus::bad_image;
    for (int i : images)
        if (i < 0 || std::size_t(i) >= images_.size()) return FrameStatus::bad_image;
    *id = int(animations_.size());
    animations_.emplace_back(images.begin(), images.end());
    return FrameStatus::ok;
}

void FrameAssembler::reserve(std::size_t sprites, AssembledFrame* out) {
    plan_.reserve(sprites);
    flat_.reserve(sprites);
    order_.reserve(sprites);
    batch_key_.reserve(sprites);
    batch_count_.reserve(sprites + 1);
    batch_start_.reserve(sprites + 1);
    const std::size_t keys = std::size_t(max_texture_ + 1) * 4;
    last_batch_of_key_.reserve(keys);
    key_rank_.reserve(keys);
    key_count_.reserve(keys);
    key_start_.reserve(keys);
    key_order_.reserve(keys);
    cell_top_.reserve(std::size_t(std::max(options_.max_cells, 1)));
    ranges_.reserve(16);
    if (out) {
        out->vertices.reserve(sprites * max_vertices_ * kVertexFloats);
        out->indices.reserve(sprites * max_indices_);
        out->draws.reserve(2 * sprites + 1);
        out->points.reserve(16);
    }
}

FrameStatus FrameAssembler::plan_sprite(std::size_t i) {
    const Sprite& s = *flat_[i];
    Plan& p = plan_[i];
    int picture = s.image;
    if (s.animation >= 0) {
        if (std::size_t(s.animation) >= animations_.size()) return FrameStatus::bad_sprite;
        const std::vector<int>& frames = animations_[std::size_t(s.animation)];
        const int n = int(frames.size());
        picture = frames[std::size_t(((s.frame % n) + n) % n)];
    }
    if (picture < 0 || std::size_t(picture) >= images_.size() || !finite_sprite(s) || int(s.blend) < 0 || int(s.blend) > 3)
        return FrameStatus::bad_sprite;
    const Picture& pic = images_[std::size_t(picture)];
    p.picture = picture;
    p.key = pic.texture * 4 + int(s.blend);
    p.batch = -1;
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

void FrameAssembler::emit(const Template& t, const Sprite& s, bool skirt, float z, AssembledFrame* out) {
    const auto base = std::uint32_t(out->vertices.size() / kVertexFloats);
    const std::size_t n = skirt ? t.xy.size() / 2 : t.plain_vertices;
    const std::size_t first = out->vertices.size();
    out->vertices.resize(first + n * kVertexFloats);
    float* v = out->vertices.data() + first;
    for (std::size_t k = 0; k < n; ++k, v += kVertexFloats) {
        const Vec2 p = apply(s.transform, {t.xy[2 * k], t.xy[2 * k + 1]});
        v[0] = float(p.x), v[1] = float(p.y), v[2] = z, v[3] = t.uv[2 * k], v[4] = t.uv[2 * k + 1];
        v[5] = s.color[0], v[6] = s.color[1], v[7] = s.color[2], v[8] = s.color[3];
    }
    const std::size_t count = skirt ? t.indices.size() : t.skirt_start;
    const std::size_t at = out->indices.size();
    out->indices.resize(at + count);
    std::uint32_t* ix = out->indices.data() + at;
    for (std::size_t k = 0; k < count; ++k) ix[k] = base + t.indices[k];
}

void FrameAssembler::emit_opaque(AssembledFrame* out) {
    // Front to back: keys by their nearest sprite, sprites nearest first
    // (append_opaque_draws' order). Levels grow with the flat index.
    const std::size_t keys = std::size_t(max_texture_ + 1) * 4;
    key_rank_.assign(keys, -1);
    key_count_.assign(keys, 0);
    key_order_.clear();
    const std::size_t n = flat_.size();
    std::size_t total = 0;
    for (std::size_t i = n; i-- > 0;) {
        const Plan& p = plan_[i];
        if (!p.opaque) continue;
        if (key_rank_[std::size_t(p.key)] < 0) {
            key_rank_[std::size_t(p.key)] = std::int32_t(key_order_.size());
            key_order_.push_back(p.key);
        }
        ++key_count_[std::size_t(p.key)];
        ++total;
    }
    if (!total) return;
    key_start_.assign(keys, 0);
    std::int32_t at = 0;
    for (std::int32_t k : key_order_) key_start_[std::size_t(k)] = at, at += key_count_[std::size_t(k)];
    order_.resize(total);
    for (std::size_t i = n; i-- > 0;)
        if (plan_[i].opaque) order_[std::size_t(key_start_[std::size_t(plan_[i].key)]++)] = std::uint32_t(i);
    std::int32_t last = -1;
    for (std::uint32_t i : order_) {
        const Plan& p = plan_[i];
        const Sprite& s = *flat_[i];
        const Picture& pic = images_[std::size_t(p.picture)];
        if (p.key != last) {
            out->draws.push_back({pic.texture, Pass::opaque, s.blend, std::uint32_t(out->indices.size()), 0});
            last = p.key;
        }
        emit(p.opaque == 2 ? pic.quad : pic.opaque[p.margin], s, false, depth_z(level_[i], true, denominator_), out);
        out->draws.back().index_count = std::uint32_t(out->indices.size()) - out->draws.back().first_index;
    }
}

void FrameAssembler::emit_blend(std::size_t begin, std::size_t end, const Viewport& bounds, AssembledFrame* out) {
    // The overlap grid over `bounds`.
    double cell = options_.cell_size > 0 && std::isfinite(options_.cell_size) ? options_.cell_size : 64;
    const double w = std::max(bounds.width, 1), h = std::max(bounds.height, 1);
    const double max_cells = std::max(options_.max_cells, 1);
    while (std::ceil(w / cell) * std::ceil(h / cell) > max_cells) cell *= 2;
    const int cols = int(std::ceil(w / cell)), rows = int(std::ceil(h / cell));
    cell_top_.assign(std::size_t(cols) * std::size_t(rows), -1);
    const std::size_t keys = std::size_t(max_texture_ + 1) * 4;
    last_batch_of_key_.assign(keys, -1);
    batch_key_.clear();
    std::int32_t all_top = -1, wide_top = -1;
    const double inv = 1 / cell;
    auto clamp_cell = [](double c, int n) { return c < 0 ? 0 : c >= n ? n - 1 : int(c); };
    for (std::size_t i = begin; i < end; ++i) {
        Plan& p = plan_[i];
        if (!p.blended) continue;
        const Sprite& s = *flat_[i];
        const Picture& pic = images_[std::size_t(p.picture)];
        double x0 = pic.bx0, y0 = pic.by0, x1 = pic.bx1, y1 = pic.by1;
        if (p.boundary == 2) x0 = 0, y0 = 0, x1 = pic.rect.w, y1 = pic.rect.h;
        double sx0 = INFINITY, sy0 = INFINITY, sx1 = -INFINITY, sy1 = -INFINITY;
        for (const Vec2 c : {Vec2{x0, y0}, Vec2{x1, y0}, Vec2{x0, y1}, Vec2{x1, y1}}) {
            const Vec2 q = apply(s.transform, c);
            sx0 = std::min(sx0, q.x), sx1 = std::max(sx1, q.x), sy0 = std::min(sy0, q.y), sy1 = std::max(sy1, q.y);
        }
        // A pixel beyond the box for GL's snapping: cells are conservative.
        const int cx0 = clamp_cell(std::floor((sx0 - 1 - bounds.x) * inv), cols);
        const int cx1 = clamp_cell(std::floor((sx1 + 1 - bounds.x) * inv), cols);
        const int cy0 = clamp_cell(std::floor((sy0 - 1 - bounds.y) * inv), rows);
        const int cy1 = clamp_cell(std::floor((sy1 + 1 - bounds.y) * inv), rows);
        const bool wide = std::int64_t(cx1 - cx0 + 1) * (cy1 - cy0 + 1) > options_.cell_budget;
        std::int32_t top = all_top;
        if (!wide) {
            top = wide_top;
            for (int cy = cy0; cy <= cy1; ++cy)
                for (int cx = cx0; cx <= cx1; ++cx) top = std::max(top, cell_top_[std::size_t(cy) * std::size_t(cols) + std::size_t(cx)]);
        } else {
            ++out->stats.over_budget;
        }
        // The earliest batch this sprite may join: after every batch of a
        // sprite it may overlap, or that very batch when it is its own key
        // (a batch draws its sprites in painter's order).
        const std::int32_t lowest = top < 0 ? 0 : batch_key_[std::size_t(top)] == p.key ? top : top + 1;
        std::int32_t b = last_batch_of_key_[std::size_t(p.key)];
        if (b < lowest) {
            b = std::int32_t(batch_key_.size());
            batch_key_.push_back(p.key);
            last_batch_of_key_[std::size_t(p.key)] = b;
        }
        p.batch = b;
        all_top = std::max(all_top, b);
        if (wide) wide_top = std::max(wide_top, b);
        else
            for (int cy = cy0; cy <= cy1; ++cy)
                for (int cx = cx0; cx <= cx1; ++cx) {
                    std::int32_t& c = cell_top_[std::size_t(cy) * std::size_t(cols) + std::size_t(cx)];
                    c = std::max(c, b);
                }
    }
    // Sprites by batch, painter's order within one (a stable counting sort).
    const std::size_t batches = batch_key_.size();
    batch_count_.assign(batches + 1, 0);
    for (std::size_t i = begin; i < end; ++i)
        if (plan_[i].blended) ++batch_count_[std::size_t(plan_[i].batch) + 1];
    for (std::size_t b = 1; b <= batches; ++b) batch_count_[b] += batch_count_[b - 1];
    order_.resize(std::size_t(batch_count_[batches]));
    for (std::size_t i = begin; i < end; ++i)
        if (plan_[i].blended) order_[std::size_t(batch_count_[std::size_t(plan_[i].batch)]++)] = std::uint32_t(i);
    std::int32_t last = -1;
    for (std::uint32_t i : order_) {
        const Plan& p = plan_[i];
        const Sprite& s = *flat_[i];
        const Picture& pic = images_[std::size_t(p.picture)];
        if (p.batch != last) {
            out->draws.push_back({pic.texture, Pass::blend, s.blend, std::uint32_t(out->indices.size()), 0});
            last = p.batch;
        }
        const float z = depth_z(level_[i], false, denominator_);
        if (p.boundary == 2) emit(pic.quad, s, false, z, out);
        else emit(pic.boundary[p.margin], s, s.blend != Blend::opaque && !snaps_exactly(s.transform), z, out);
        out->draws.back().index_count = std::uint32_t(out->indices.size()) - out->draws.back().first_index;
    }
}

FrameStatus FrameAssembler::run(const Viewport& bounds, AssembledFrame* out) {
    const std::size_t n = flat_.size();
    plan_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        if (FrameStatus st = plan_sprite(i); st != FrameStatus::ok) return st;
    out->vertices.clear();
    out->indices.clear();
    out->draws.clear();
    out->points.clear();
    out->stats = {};
    out->stats.sprites = std::int64_t(n);
    out->depth_test = options_.opaque_pass;
    out->depth_denominator = denominator_;
    emit_opaque(out);
    out->opaque_draws = out->draws.size();
    for (const FramePoint& r : ranges_) {
        FramePoint point;
        point.static_draw = r.static_draw;
        point.first_draw = std::uint32_t(out->draws.size());
        emit_blend(r.first_draw, r.end_draw, bounds, out);
        point.end_draw = std::uint32_t(out->draws.size());
        out->points.push_back(point);
    }
    out->stats.draw_calls = std::int64_t(out->draws.size());
    out->stats.opaque_draws = std::int64_t(out->opaque_draws);
    out->stats.blend_batches = out->stats.draw_calls - out->stats.opaque_draws;
    out->stats.triangles = std::int64_t(out->indices.size() / 3);
    return FrameStatus::ok;
}

FrameStatus FrameAssembler::assemble(std::span<const Sprite> sprites, const Viewport& bounds, AssembledFrame* out) {
    if (!out) return FrameStatus::bad_sprite;
    if (std::int64_t(sprites.size()) > kMaxDepthLevels) return FrameStatus::too_many_sprites;
    flat_.clear();
    level_.resize(sprites.size());
    for (std::size_t i = 0; i < sprites.size(); ++i) flat_.push_back(&sprites[i]), level_[i] = std::int64_t(i);
    denominator_ = depth_denominator(std::int64_t(sprites.size()));
    ranges_.clear();
    ranges_.push_back({0, 0, std::uint32_t(sprites.size())});
    return run(bounds, out);
}

FrameStatus FrameAssembler::assemble_at(const SceneMeshes& static_meshes, std::span<const std::span<const Sprite>> sprites,
                                        const Viewport& bounds, AssembledFrame* out) {
    if (!out || sprites.size() > static_meshes.insertion_points.size() || static_meshes.depth_denominator < 2)
        return FrameStatus::bad_meshes;
    flat_.clear();
    level_.clear();
    ranges_.clear();
    for (std::size_t k = 0; k < sprites.size(); ++k) {
        const InsertionPoint& point = static_meshes.insertion_points[k];
        if (std::int64_t(sprites[k].size()) > point.levels) return FrameStatus::too_many_sprites;
        const auto first = std::uint32_t(flat_.size());
        for (std::size_t i = 0; i < sprites[k].size(); ++i) {
            flat_.push_back(&sprites[k][i]);
            level_.push_back(point.first_level + std::int64_t(i));
        }
        ranges_.push_back({point.blend_draw, first, std::uint32_t(flat_.size())});
    }
    denominator_ = static_meshes.depth_denominator;
    const FrameStatus st = run(bounds, out);
    out->depth_test = static_meshes.depth_test;
    return st;
}

} // namespace depthcull
