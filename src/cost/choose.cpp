// --target: choosing each image's and element's analysis for the lowest
// predicted frame time (docs/cost-model.md, "Choosing").
//
// 1. Per image rect (key), the boundary among the candidates (vertex
//    budgets) and the whole rect, by the summed blend-pass cost of its
//    uses: triangles (with the texel skirts the runtime adds where GL
//    snaps vertices), their perimeter, and the fragments.
// 2. Per element, its opaque polygons (none, the first, all), by what
//    they cost in the opaque pass against the blend-pass fragments they
//    turn into rejected ones: the element's own and, through the element
//    graph, those of the elements behind it under them.
// 3. Elements one opaque polygon in front hides completely are dropped:
//    exact, so the look never changes.
// 4. The choice is checked on the whole frame with the model (meshes
//    rasterized on the CPU) against meshes only, the paper's defaults and
//    plainer fallbacks; the lowest prediction wins, so the output is never
//    predicted slower than meshes only.
// 5. For the images used most, the winner is tried again with their
//    opaque polygons given up, then their plain rect (fall_back).
//
// choose_for_target runs the steps in order; Chooser holds what they share.
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "depthcull/cost.h"
#include "scene/internal.h"
#include "scene/placement.h"

namespace depthcull {

namespace {

struct Geometry {
    double triangles = 0, perimeter = 0, area = 0; // texels
    double edges = 0, outline = 0;                 // polygon edges and their length, for texel skirts
};

double polygon_area(const Polygon& p) {
    double a = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec2 &u = p[i], &v = p[(i + 1) % p.size()];
        a += u.x * v.y - v.x * u.y;
    }
    return std::abs(a) / 2;
}

Geometry geometry_of(const std::vector<Polygon>& polygons, bool convex) {
    Geometry g;
    for (const Polygon& p : polygons) {
        if (p.size() < 3) continue;
        std::vector<std::uint32_t> tri;
        if (convex) {
            for (std::uint32_t k = 1; k + 1 < p.size(); ++k) tri.insert(tri.end(), {0, k, k + 1});
        } else {
            tri = triangulate_polygon(p);
        }
        for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
            g.triangles += 1;
            for (int k = 0; k < 3; ++k) {
                const Vec2 &a = p[tri[t + std::size_t(k)]], &b = p[tri[t + std::size_t((k + 1) % 3)]];
                g.perimeter += std::hypot(b.x - a.x, b.y - a.y);
            }
        }
        g.area += polygon_area(p);
        for (std::size_t i = 0; i < p.size(); ++i) {
            g.edges += 1;
            g.outline += std::hypot(p[(i + 1) % p.size()].x - p[i].x, p[(i + 1) % p.size()].y - p[i].y);
        }
    }
    return g;
}

Polygon rect_polygon_of(const Rect& r) {
    const double x0 = r.x, y0 = r.y, x1 = double(r.x) + r.w, y1 = double(r.y) + r.h;
    return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

bool inside_rect(const std::vector<Polygon>& polygons, const Rect& r) {
    for (const Polygon& p : polygons)
        for (const Vec2& v : p)
            if (v.x < r.x || v.y < r.y || v.x > double(r.x) + r.w || v.y > double(r.y) + r.h) return false;
    return true;
}

struct ScreenBox {
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
};

// Area of convex polygon p clipped to box b.
double clipped_area(const Polygon& p, const ScreenBox& b) {
    Polygon cur = p, next;
    auto clip = [&](auto inside, auto cross) {
        next.clear();
        for (std::size_t i = 0; i < cur.size(); ++i) {
            const Vec2 a = cur[i], c = cur[(i + 1) % cur.size()];
            const bool ia = inside(a), ic = inside(c);
            if (ia) next.push_back(a);
            if (ia != ic) next.push_back(cross(a, c));
        }
        std::swap(cur, next);
    };
    auto at_x = [](double x) {
        return [x](Vec2 a, Vec2 c) { return Vec2{x, a.y + (c.y - a.y) * (x - a.x) / (c.x - a.x)}; };
    };
    auto at_y = [](double y) {
        return [y](Vec2 a, Vec2 c) { return Vec2{a.x + (c.x - a.x) * (y - a.y) / (c.y - a.y), y}; };
    };
    clip([&](Vec2 v) { return v.x >= b.x0; }, at_x(b.x0));
    if (cur.size() >= 3) clip([&](Vec2 v) { return v.x <= b.x1; }, at_x(b.x1));
    if (cur.size() >= 3) clip([&](Vec2 v) { return v.y >= b.y0; }, at_y(b.y0));
    if (cur.size() >= 3) clip([&](Vec2 v) { return v.y <= b.y1; }, at_y(b.y1));
    return cur.size() >= 3 ? polygon_area(cur) : 0;
}

// Opaque variants of an element.
enum Opaque : int { none = 0, first = 1, all = 2 };

struct Variant {
    int key = -1, boundary = -1, opaque = Opaque::all;
    bool dropped = false;
    bool operator<(const Variant& o) const {
        return std::tie(key, boundary, opaque, dropped) < std::tie(o.key, o.boundary, o.opaque, o.dropped);
    }
};

ImageAnalysis make_variant(const TargetCandidates& c, const Variant& v) {
    const ImageAnalysis& cap = *c.analyses.back();
    ImageAnalysis a = v.boundary >= 0 ? *c.analyses[std::size_t(v.boundary)] : cap;
    a.stats = cap.stats;
    if (v.boundary < 0 && !cap.boundary.empty()) a.boundary = {rect_polygon_of(cap.rect)};
    a.opaque = cap.opaque;
    if (v.opaque == Opaque::first && a.opaque.size() > 1) {
        a.opaque.resize(1);
        a.stats.opaque_covered_texels = 0; // the element keeps its blend draw
    }
    if (v.opaque == Opaque::none) {
        a.opaque.clear();
        a.stats.opaque_texels = 0; // nor the whole-rect opaque rule
        a.stats.opaque_covered_texels = 0;
    }
    if (v.dropped) {
        a.boundary.clear();
        a.opaque.clear();
        a.stats.opaque_texels = 0;
        a.stats.opaque_covered_texels = 0;
    }
    return a;
}

struct Contestant {
    std::string name;
    std::vector<Variant> variants; // per element
    bool opaque_pass = true;
    bool depthless = false; // ReconstructOptions::depthless (issue 25)
    std::size_t origin = 0; // for a depthless twin, the index of the contestant it draws without depth
};

// Clipping planned (issue 25): the edges a cut adds, as a multiple of the
// occluder's outline, and the triangles, per element cut (Chooser::cut_cost).
constexpr double kCutEdges = 5.0;
constexpr double kCutTriangles = 4.0;

// The state the steps share: the inputs, what each element's placement
// gives the model, and what each step decided. One function per step.
struct Chooser {
    const Scene& scene;
    const std::vector<TargetCandidates>& candidates;
    const std::vector<int>& element_key;
    const CostProfile& P;
    const ReconstructOptions& options;
    std::size_t n = 0, keys = 0;
    double T = 0, Pp = 0, Fb = 0, Fo = 0, Fr = 0;

    // Element placement.
    std::vector<double> det, stretch;
    std::vector<std::uint8_t> skirt, choosable;
    // 1.
    std::vector<std::vector<Geometry>> boundary_geo;
    std::vector<Geometry> rect_geo;
    std::vector<std::vector<std::uint8_t>> boundary_ok;
    std::vector<int> choice;
    std::vector<Variant> variants;
    std::vector<ScreenBox> box;
    std::vector<std::vector<Polygon>> drawn;
    // 2.
    ElementGraph graph;
    std::vector<std::vector<Polygon>> occluder; // screen polygons of the opaque polygons drawn
    std::vector<std::uint8_t> whole_rect;
    bool opaque_pass = false;
    // 3.
    // The elements each one's opaque polygon hides (CSR: hides[hides_begin[j]
    // .. hides_begin[j + 1]]), so that reverting one element's opaque polygons
    // costs what it hid, not a pass over the scene: fall_back reverts every
    // element of a key, and a scan per element was quadratic (500,000 tiles
    // of one key took minutes).
    std::vector<std::size_t> hides_begin;
    std::vector<std::uint32_t> hides;
    // evaluate()'s cuts, kept from one contestant frame to the next: most
    // cut their elements alike (ClipHiddenOptions::memo).
    std::unique_ptr<detail::ClipMemo, detail::ClipMemoDelete> clip_memo = detail::make_clip_memo();
    // And their element graphs: most draw the same boundary polygons
    // (ReconstructOptions::graph_memo).
    std::unique_ptr<detail::GraphMemo, detail::GraphMemoDelete> graph_memo = detail::make_graph_memo();

    // Issue 25: with hidden parts clipped, what an opaque polygon hides is
    // not drawn at all instead of rejected (a bound: the cut may not pay).
    Chooser(const Scene& s, const std::vector<TargetCandidates>& c, const std::vector<int>& k, const CostProfile& p,
            const ReconstructOptions& o)
        : scene(s), candidates(c), element_key(k), P(p), options(o), n(s.elements.size()), keys(c.size()), T(p.triangle_us * 1e3),
          Pp(p.triangle_perimeter_ns_per_pixel), Fb(p.fragment_blend_ns), Fo(p.fragment_opaque_ns), Fr(o.clip_hidden.enabled && o.clip_hidden.plan_occluders ? 0.0 : p.fragment_rejected_ns) {}

    int key_of(std::size_t i) const { return i < element_key.size() ? element_key[i] : -1; }
    bool usable(std::size_t i) const {
        const int k = key_of(i);
        return k >= 0 && std::size_t(k) < keys && !candidates[std::size_t(k)].analyses.empty() &&
               candidates[std::size_t(k)].analyses.back() != nullptr;
    }
    double blend_cost(std::size_t i, const Geometry& g, bool with_skirt) const {
        const double s = std::sqrt(det[i]);
        double ns = T * g.triangles + Pp * g.perimeter * s + Fb * g.area * det[i];
        if (with_skirt && skirt[i]) ns += T * 2 * g.edges + Pp * 4 * g.outline * s; // two slivers per edge
        return ns;
    }
    std::vector<Polygon> chosen_boundary(std::size_t i) const {
        const std::size_t k = std::size_t(key_of(i));
        const TargetCandidates& c = candidates[k];
        if (choice[k] < 0 || !boundary_ok[k][std::size_t(choice[k])]) return {rect_polygon_of(c.analyses.back()->rect)};
        return c.analyses[std::size_t(choice[k])]->boundary;
    }
    // Screen geometry of what element i draws.
    Polygon to_screen(std::size_t i, const Polygon& p) const {
        const Element& e = scene.elements[i];
        Polygon out;
        out.reserve(p.size());
        for (const Vec2& v : p) out.push_back(apply(e.transform, {v.x - e.rect.x, v.y - e.rect.y}));
        return out;
    }

    void place_elements();
    void choose_boundaries();          // 1
    struct OpaqueOption {
        int opaque;                  // Opaque::first or all
        double delta;                // predicted ns per frame: negative pays
        std::vector<Polygon> screen; // the polygons on screen
        bool rect;                   // the whole rect (an opaque tile)
    };
    bool cuts() const;
    double cut_cost(std::size_t j, const std::vector<Polygon>& texel) const;
    double behind_gain(std::size_t j, const std::vector<Polygon>& screen, double cut) const;
    std::vector<OpaqueOption> opaque_options(std::size_t j) const;
    void choose_opaque();              // 2
    void drop_hidden();                // 3
    std::vector<Contestant> contestants() const; // 4
    double evaluate(const Contestant& c, SceneAnalysis* analysis) const;
    void fall_back(Contestant& win, double& best_ms, TargetChoice& out) const; // 5
};

void Chooser::place_elements() {
    det.assign(n, 0);
    stretch.assign(n, 0);
    skirt.assign(n, 0);
    choosable.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const Element& e = scene.elements[i];
        const auto& m = e.transform;
        det[i] = std::abs(m[0] * m[3] - m[1] * m[2]);
        stretch[i] = std::max(std::hypot(m[0], m[1]), std::hypot(m[2], m[3]));
        if (!std::isfinite(det[i])) det[i] = 0;
        skirt[i] = options.texel_margin > 0 && !detail::snaps_exactly(m);
        choosable[i] = usable(i) && (e.blend == Blend::alpha || e.blend == Blend::add) && e.color[3] > 0.0f;
    }
}

// 1. Boundaries per key.
void Chooser::choose_boundaries() {
    boundary_geo.assign(keys, {});
    rect_geo.assign(keys, {});
    boundary_ok.assign(keys, {});
    for (std::size_t k = 0; k < keys; ++k) {
        const TargetCandidates& c = candidates[k];
        if (c.analyses.empty() || !c.analyses.back()) continue;
        const Rect r = c.analyses.back()->rect;
        rect_geo[k] = geometry_of({rect_polygon_of(r)}, true);
        rect_geo[k].edges = 0; // a rect's skirt is clipped away
        for (const ImageAnalysis* a : c.analyses) {
            boundary_geo[k].push_back(a ? geometry_of(a->boundary, false) : Geometry{});
            boundary_ok[k].push_back(a && inside_rect(a->boundary, r) && !a->boundary.empty());
        }
    }
    choice.assign(keys, -1);
    {
        std::vector<std::vector<double>> sum(keys);
        std::vector<double> rect_sum(keys, 0);
        for (std::size_t k = 0; k < keys; ++k) sum[k].assign(boundary_geo[k].size(), 0);
        for (std::size_t i = 0; i < n; ++i) {
            if (!choosable[i]) continue;
            const std::size_t k = std::size_t(key_of(i));
            rect_sum[k] += blend_cost(i, rect_geo[k], false);
            for (std::size_t c = 0; c < sum[k].size(); ++c)
                sum[k][c] += boundary_ok[k][c] ? blend_cost(i, boundary_geo[k][c], true) : blend_cost(i, rect_geo[k], false);
        }
        for (std::size_t k = 0; k < keys; ++k) {
            // Default to the last (the paper's budget) when nothing uses it.
            choice[k] = boundary_geo[k].empty() ? -1 : int(boundary_geo[k].size()) - 1;
            double best = INFINITY;
            if (!boundary_geo[k].empty() && rect_sum[k] == 0 && sum[k].back() == 0) continue;
            for (std::size_t c = 0; c < sum[k].size(); ++c)
                if (boundary_ok[k][c] && sum[k][c] < best) best = sum[k][c], choice[k] = int(c);
            if (rect_sum[k] < best) choice[k] = -1;
        }
    }

    variants.assign(n, Variant{});
    for (std::size_t i = 0; i < n; ++i)
        if (usable(i)) variants[i] = {key_of(i), choice[std::size_t(key_of(i))], Opaque::all, false};

    box.assign(n, ScreenBox{});
    drawn.assign(n, {});
    for (std::size_t i = 0; i < n; ++i) {
        if (!usable(i)) continue;
        for (const Polygon& p : chosen_boundary(i)) {
            drawn[i].push_back(to_screen(i, p));
            for (const Vec2& v : drawn[i].back())
                box[i].x0 = std::min(box[i].x0, v.x), box[i].y0 = std::min(box[i].y0, v.y), box[i].x1 = std::max(box[i].x1, v.x),
                box[i].y1 = std::max(box[i].y1, v.y);
        }
    }
}

// Clipping planned (issue 25): each element behind an opaque polygon (and
// the element's own blend polygons) is cut along it: new edges of about
// kCutEdges times its outline (the cut edge and the diagonals its pieces
// need) and kCutTriangles triangles, which llvmpipe prices like fragments
// (6.8 ns per pixel of edge). Priced as free, the plan took every opaque
// polygon and lost more on edges than it saved.
bool Chooser::cuts() const { return options.clip_hidden.enabled && options.clip_hidden.plan_occluders; }

double Chooser::cut_cost(std::size_t j, const std::vector<Polygon>& texel) const {
    // Edges on the element's rect's sides (opaque_to_rect_sides; side_margins
    // gives them no margin) add no edge to a tile under it in the same cell:
    // it is cut along its own side (clip_hidden.cpp).
    double outline = 0;
    for (const Polygon& p : texel) {
        const std::vector<double> margin = detail::side_margins(scene, scene.elements[j], p, 1.0);
        const Polygon s = to_screen(j, p);
        for (std::size_t q = 0; q < s.size(); ++q)
            if (margin[q] > 0) outline += std::hypot(s[(q + 1) % s.size()].x - s[q].x, s[(q + 1) % s.size()].y - s[q].y);
    }
    return kCutEdges * Pp * outline + kCutTriangles * T;
}

// What opaque polygons at `screen` save on the elements behind element j,
// less `cut` (cut_cost, or 0 when nothing is cut) for each one they cover.
double Chooser::behind_gain(std::size_t j, const std::vector<Polygon>& screen, double cut) const {
    double area = 0, overhead = 0;
    for (const std::uint32_t* b = graph.behind_begin(j); b != graph.behind_end(j); ++b) {
        double a = 0;
        for (const Polygon& p : screen) a += clipped_area(p, box[*b]);
        area += a;
        if (a > 0) overhead += cut;
    }
    return area * (Fb - Fr) - overhead;
}

// Element j's choices of opaque polygons, each with its predicted change
// of the frame time (negative: it pays).
std::vector<Chooser::OpaqueOption> Chooser::opaque_options(std::size_t j) const {
    std::vector<OpaqueOption> out;
    const Element& e = scene.elements[j];
    const std::size_t k = std::size_t(key_of(j));
    const ImageAnalysis& cap = *candidates[k].analyses.back();
    const double s = std::sqrt(det[j]);
    const Geometry own = choice[k] >= 0 && boundary_ok[k][std::size_t(choice[k])] ? boundary_geo[k][std::size_t(choice[k])] : rect_geo[k];
    const double own_blend = blend_cost(j, own, true);
    if (cap.stats.opaque_texels == std::int64_t(cap.rect.w) * cap.rect.h && detail::pixel_aligned(scene, e)) {
        // Whole-rect opaque: the rect in the opaque pass, no blend draw.
        const Geometry g = rect_geo[k];
        const std::vector<Polygon> rect{rect_polygon_of(cap.rect)};
        std::vector<Polygon> screen{to_screen(j, rect[0])};
        const double cost = T * g.triangles + Pp * g.perimeter * s + Fo * g.area * det[j];
        const double delta = cost - own_blend - behind_gain(j, screen, cuts() ? cut_cost(j, rect) : 0.0);
        out.push_back({Opaque::all, delta, std::move(screen), true});
        return out;
    }
    for (int o : {int(Opaque::first), int(Opaque::all)}) {
        if (cap.opaque.empty() || (o == Opaque::all && cap.opaque.size() == 1)) continue;
        std::vector<Polygon> polys(cap.opaque.begin(), o == Opaque::first ? cap.opaque.begin() + 1 : cap.opaque.end());
        for (Polygon& p : polys) p = detail::opaque_to_rect_sides(scene, e, p); // as reconstruction draws them
        const Geometry g = geometry_of(polys, true);
        std::vector<Polygon> screen;
        for (const Polygon& p : polys) screen.push_back(to_screen(j, p));
        const double cut = cuts() ? cut_cost(j, polys) : 0.0;
        const double cost = T * g.triangles + Pp * g.perimeter * s + Fo * g.area * det[j] + cut;
        const double behind = behind_gain(j, screen, cut);
        double gain = (Fb - Fr) * g.area * det[j] + behind;
        if (o == Opaque::all && scene.filter == Filter::nearest && cap.stats.nontransparent_texels > 0 &&
            cap.stats.opaque_covered_texels == cap.stats.nontransparent_texels && choice[k] >= 0)
            gain = own_blend + behind; // no blend draw at all
        out.push_back({o, cost - gain, std::move(screen), false});
    }
    return out;
}

void Chooser::choose_opaque() {
    // 2. Opaque polygons per element, over the element graph.
    std::vector<ImageAnalysis> plain(n);
    std::vector<const ImageAnalysis*> plain_ptr(n, nullptr);
    for (std::size_t i = 0; i < n; ++i)
        if (usable(i)) {
            plain[i].rect = candidates[std::size_t(key_of(i))].analyses.back()->rect;
            plain[i].boundary = chosen_boundary(i);
            plain_ptr[i] = &plain[i];
        }
    graph = build_element_graph(scene, plain_ptr, GraphMode::polygons, options.graph_pair_budget);
    occluder.assign(n, {});
    whole_rect.assign(n, 0);
    double opaque_gain = 0;
    std::int64_t opaque_count = 0;
    for (std::size_t j = 0; j < n; ++j) {
        const Element& e = scene.elements[j];
        if (!usable(j)) continue;
        variants[j].opaque = Opaque::none;
        if (e.blend != Blend::alpha || e.color[3] != 1.0f) continue;
        std::vector<OpaqueOption> options_j = opaque_options(j);
        OpaqueOption* best = nullptr;
        for (OpaqueOption& o : options_j)
            if (o.delta < 0 && (!best || o.delta < best->delta)) best = &o;
        if (!best) continue;
        variants[j].opaque = best->opaque;
        occluder[j] = std::move(best->screen);
        whole_rect[j] = best->rect;
        opaque_gain += -best->delta;
        ++opaque_count;
    }
    const double depth_ns = P.clear_depth_ns_per_pixel * double(scene.viewport.width) * double(scene.viewport.height);
    opaque_pass = opaque_count > 0 && opaque_gain > depth_ns;
}

void Chooser::drop_hidden() {
    // 3. Elements hidden by one opaque polygon in front.
    const std::vector<std::vector<std::uint32_t>> front = graph.in_front();
    std::vector<std::int64_t> hider(n, -1); // the element whose opaque polygon hides it
    if (opaque_pass)
        for (std::size_t i = 0; i < n; ++i) {
            if (!choosable[i] || drawn[i].empty()) continue;
            const double grow = skirt[i] ? options.texel_margin * stretch[i] : 0;
            for (std::uint32_t j : front[i]) {
                if (occluder[j].empty()) continue;
                // Exact when both rasterize without snapping and the
                // occluder is a pixel-aligned rect (no pixel centre on
                // its edges); else a margin beyond snapping and skirts.
                const bool exact = whole_rect[j] && !skirt[i];
                const double margin = exact ? 0 : grow + (whole_rect[j] ? 0 : options.texel_margin * stretch[j]) + 1.0 / 64;
                bool hidden = false;
                for (const Polygon& P_ : occluder[j]) {
                    double a2 = 0; // twice the signed area: its sign says which side is inside
                    for (std::size_t q = 0; q < P_.size(); ++q) a2 += P_[q].x * P_[(q + 1) % P_.size()].y - P_[(q + 1) % P_.size()].x * P_[q].y;
                    const double orient_sign = a2 > 0 ? 1 : -1;
                    bool all_in = true;
                    for (const Polygon& p : drawn[i]) {
                        for (const Vec2& v : p) {
                            for (std::size_t q = 0; q < P_.size() && all_in; ++q) {
                                const Vec2 a = P_[q], b = P_[(q + 1) % P_.size()];
                                const double len = std::hypot(b.x - a.x, b.y - a.y);
                                if (!(len > 0)) continue;
                                const double d = orient_sign * ((b.x - a.x) * (v.y - a.y) - (b.y - a.y) * (v.x - a.x)) / len;
                                if (!(d >= margin)) all_in = false;
                            }
                            if (!all_in) break;
                        }
                        if (!all_in) break;
                    }
                    if (all_in) {
                        hidden = true;
                        break;
                    }
                }
                if (hidden) {
                    variants[i].dropped = true;
                    hider[i] = std::int64_t(j);
                    break;
                }
            }
        }
    hides_begin.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i)
        if (hider[i] >= 0) ++hides_begin[std::size_t(hider[i]) + 1];
    for (std::size_t j = 0; j < n; ++j) hides_begin[j + 1] += hides_begin[j];
    hides.assign(hides_begin[n], 0);
    std::vector<std::size_t> fill(hides_begin.begin(), hides_begin.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
        if (hider[i] >= 0) hides[fill[std::size_t(hider[i])]++] = std::uint32_t(i);
}

std::vector<Contestant> Chooser::contestants() const {
    // 4. Contestants, predicted on the whole frame.
    std::vector<Contestant> out;
    out.push_back({"", variants, opaque_pass});
    {
        Contestant c{"no dropped elements", variants, opaque_pass};
        for (Variant& v : c.variants) v.dropped = false;
        out.push_back(c);
        Contestant d{"no opaque polygons", c.variants, false};
        for (Variant& v : d.variants) v.opaque = Opaque::none;
        out.push_back(d);
        Contestant r{"rects (meshes only)", d.variants, false};
        for (Variant& v : r.variants) v.boundary = -1;
        out.push_back(r);
        Contestant paper{"every opaque polygon at the vertex cap", {}, true};
        for (std::size_t i = 0; i < n; ++i)
            paper.variants.push_back(usable(i) ? Variant{key_of(i), int(candidates[std::size_t(key_of(i))].analyses.size()) - 1, Opaque::all, false}
                                               : Variant{});
        out.push_back(paper);
    }
    for (std::size_t k = 0; k < out.size(); ++k) out[k].origin = k;
    // Each with opaque polygons also drawn without depth where the caller
    // allows it: the same choices, the opaque pass back to front. Also when
    // step 2 left the opaque pass off: the gain it weighed against was the
    // depth buffer's.
    if (options.depthless) {
        const std::size_t count = out.size();
        for (std::size_t k = 0; k < count; ++k)
            if (std::any_of(out[k].variants.begin(), out[k].variants.end(), [](const Variant& v) { return v.opaque != Opaque::none; })) {
                Contestant twin = out[k];
                twin.opaque_pass = true;
                twin.depthless = true;
                out.push_back(std::move(twin));
            }
    }
    return out;
}

// The frame predicted for a contestant (INFINITY if it cannot be built).
double Chooser::evaluate(const Contestant& c, SceneAnalysis* analysis) const {
    std::map<Variant, std::uint32_t> index;
    analysis->images.clear();
    analysis->of_element.assign(n, UINT32_MAX); // past images: of() gives nullptr
    for (std::size_t i = 0; i < n; ++i) {
        if (!usable(i)) continue;
        auto [it, fresh] = index.emplace(c.variants[i], std::uint32_t(analysis->images.size()));
        if (fresh) analysis->images.push_back(make_variant(candidates[std::size_t(key_of(i))], c.variants[i]));
        analysis->of_element[i] = it->second;
    }
    ReconstructOptions o = options;
    o.opaque_polygons = c.opaque_pass;
    o.depthless = c.depthless; // twins always have an opaque pass
    o.clip_hidden.memo = clip_memo.get();
    o.graph_memo = graph_memo.get();
    SceneMeshes m;
    if (reconstruct_scene(scene, analysis->per_element(), o, &m) != ReconstructStatus::ok) return double(INFINITY);
    // A twin whose opaque polygons all moved to the blend pass has no
    // opaque pass to draw without depth: it is another plan without opaque
    // polygons, which the contestants already hold.
    if (o.depthless && std::none_of(m.draws.begin(), m.draws.end(), [](const Draw& d) { return d.pass == Pass::opaque; }))
        return double(INFINITY);
    return predict_ms(P, frame_features(m));
}

void Chooser::fall_back(Contestant& win, double& best_ms, TargetChoice& out) const {
    // 5. Per element fallback, image by image: the local estimates of 1
    // and 2 miss what the whole frame shows (blocks the rasterizer shades
    // whole, fragments behind several occluders), so for the images used
    // most, the winner is predicted again with that image's elements
    // drawing no opaque polygons (and what they hid drawn again), then with
    // its plain rect as boundary; a change is kept only when the frame is
    // predicted faster, so the result stays no slower than meshes only.
    if (std::isfinite(best_ms) && keys > 0) {
        std::vector<std::int64_t> uses(keys, 0);
        for (std::size_t i = 0; i < n; ++i)
            if (usable(i) && !win.variants[i].dropped) ++uses[std::size_t(key_of(i))];
        std::vector<std::size_t> order(keys);
        for (std::size_t k = 0; k < keys; ++k) order[k] = k;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return uses[a] > uses[b]; });
        constexpr std::size_t kMaxKeysTried = 12; // bounds the time: each try rasterizes the frame
        SceneAnalysis scratch;
        for (std::size_t r = 0; r < std::min(kMaxKeysTried, keys) && uses[order[r]] > 0; ++r) {
            const int k = int(order[r]);
            if (win.opaque_pass) {
                Contestant t = win;
                bool changed = false;
                for (std::size_t i = 0; i < n; ++i)
                    if (usable(i) && key_of(i) == k && t.variants[i].opaque != Opaque::none && !t.variants[i].dropped) {
                        t.variants[i].opaque = Opaque::none;
                        changed = true;
                        for (std::size_t h = hides_begin[i]; h < hides_begin[i + 1]; ++h) t.variants[hides[h]].dropped = false;
                    }
                if (changed) {
                    const double ms = evaluate(t, &scratch);
                    if (ms < best_ms) {
                        best_ms = ms, win = t;
                        for (std::size_t i = 0; i < n; ++i) out.elements_reverted += usable(i) && key_of(i) == k && !win.variants[i].dropped;
                    }
                }
            }
            {
                Contestant t = win;
                bool changed = false;
                for (std::size_t i = 0; i < n; ++i)
                    if (usable(i) && key_of(i) == k && t.variants[i].boundary >= 0) t.variants[i].boundary = -1, changed = true;
                if (changed) {
                    const double ms = evaluate(t, &scratch);
                    if (ms < best_ms) best_ms = ms, win = t, out.key_choice[std::size_t(k)] = -1;
                }
            }
        }
    }
}

} // namespace

TargetChoice choose_for_target(const Scene& scene, const std::vector<TargetCandidates>& candidates,
                               const std::vector<int>& element_key, const CostProfile& P, const ReconstructOptions& options) {
    Chooser c(scene, candidates, element_key, P, options);
    c.place_elements();
    c.choose_boundaries();
    c.choose_opaque();
    c.drop_hidden();
    const std::vector<Contestant> contestants = c.contestants();

    TargetChoice out;
    out.key_choice = c.choice;
    {
        SceneMeshes m;
        if (rectangle_meshes(scene, options, &m) == ReconstructStatus::ok) out.meshes_only_ms = predict_ms(P, frame_features(m));
        out.overpaint_ms = predict_ms(P, frame_features(overpaint_meshes(scene)));
    }
    double best_ms = INFINITY;
    std::size_t best = 0;
    {
        SceneAnalysis scratch;
        for (std::size_t ci = 0; ci < contestants.size(); ++ci) {
            const double ms = c.evaluate(contestants[ci], &scratch);
            if (ms < best_ms) best_ms = ms, best = ci; // first wins ties: deterministic
        }
    }
    Contestant win = contestants[best];
    if (win.origin == 3) std::fill(out.key_choice.begin(), out.key_choice.end(), -1); // rects everywhere
    if (win.origin == 4)
        for (std::size_t k = 0; k < c.keys; ++k) out.key_choice[k] = int(candidates[k].analyses.size()) - 1;

    c.fall_back(win, best_ms, out); // 5.
    out.predicted_ms = c.evaluate(win, &out.analysis);
    out.opaque_pass = win.opaque_pass;
    out.depthless = win.depthless;
    out.fallback = win.name;
    for (std::size_t i = 0; i < c.n; ++i) {
        out.elements_dropped += win.variants[i].dropped;
        out.elements_opaque += c.usable(i) && win.opaque_pass && !win.variants[i].dropped && win.variants[i].opaque != Opaque::none &&
                               !out.analysis.of(i)->opaque.empty();
    }
    return out;
}

std::vector<int> target_budgets(int max_vertices) {
    const int cap = std::max(kMinBoundaryVertices, max_vertices);
    std::vector<int> budgets;
    for (int b : {4, 6, 8})
        if (b < cap) budgets.push_back(b);
    budgets.push_back(cap);
    return budgets;
}

} // namespace depthcull
