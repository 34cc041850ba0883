// Issue 25, point 3: clipping hidden parts (ReconstructOptions::clip_hidden).
//
// An element B behind the opaque polygons of elements in front (nearer
// depth levels, drawn in the opaque pass) draws fragments there that the
// depth test rejects. Here that part of B's blend-pass polygons (or of its
// whole-rect opaque tile) is cut away on the CPU with Clipper 6, in exact
// integers of 2^-32 screen pixel, so GL never rasterizes it.
//
// Why the look cannot change (pixel identity with overpaint):
// - The cut region C' is each occluder's opaque polygon as GL gets it
//   (pulled in by the texel margin, transformed, in floats) shrunk by
//   `margin` (1/16 px), far more than GL's snapping (1/512 px per
//   coordinate) and the float rounding of the clipped vertices (< 2^-11 px
//   on screens under 8192 px): a pixel centre B still misses near a cut
//   edge lies inside the occluder as GL draws it, where the occluder wins
//   the depth test whatever B draws.
// - Along the rect's sides of an occluder placed on whole pixels (nearest
//   filtering) there is no margin: its opaque polygons reach those sides
//   (opaque_to_rect_sides, side_margins), which lie on whole pixels where
//   GL snaps nothing, and the polygon's edge there is the rect's own line.
//   An element behind that shares the side (a tile under a tile) is cut
//   up to it exactly and keeps no rim to draw.
// - A cut vertex on B's own outline is pushed 1/64 px outward (and put back
//   onto the rect where the push left it): the piece then covers all of
//   B's polygon along that edge despite rounding. Outside B's boundary
//   polygons every texel is transparent (paper 2.1), so the extra sliver
//   blends nothing; on the rect edge the clamp puts the vertex exactly on
//   the rect's line, which only an element that GL snaps exactly keeps
//   straight.
// - Elements GL does not snap exactly (turned, scaled anyhow, flipped,
//   moved off the 1/256 grid; issue 25 point 3) are cut only where no new
//   vertex can land on their rect's outline: the cut is first intersected
//   with the rect shrunk by `margin` on screen, so every cut vertex lies
//   that far inside the rect, and a vertex pushed off an inner edge of B's
//   polygons stays inside it (no clamp: an element whose push would leave
//   the rect is not cut).
// - B's original vertices are kept bit for bit, and its skirts are drawn
//   around its original polygons as before.
// - What is left is triangulated whole, holes included (an occluder inside
//   B touching none of its edges: triangulate_holes.cpp), on Clipper's
//   exact grid, and the triangles are checked again where B draws them
//   (texel space, after the pushes): none turns over, and their areas sum
//   to the region's. On screen none is thinner than kMinHeight, so GL's
//   rounding turns none over either (a sliver between nearly collinear
//   cut points, with zero area on the exact grid, turned over would cover
//   pixel centres beside it twice with its neighbours), and none is a
//   needle (kMaxAspect), whose texture coordinates GL interpolates too
//   loosely; the triangulation takes no diagonal passing that close to a
//   point, which leaves most such regions another way to be cut. Only
//   where that fails (over 64 points, contours that touch) is B, when GL
//   snaps it exactly, cut into strips at whole-pixel x instead
//   (strip_groups).
// Per element, the cut is kept only when the rejected fragments it saves
// beat the triangles and perimeter it adds, at the caller's costs.
#include <algorithm>
#include <cmath>
#include <map>

#include "scene/internal.h"
#include "scene/placement.h"

#ifdef DEPTHCULL_HAVE_CLIPPER
#include <polyclipping/clipper.hpp>
#endif

namespace depthcull::detail {

#ifndef DEPTHCULL_HAVE_CLIPPER

struct ClipMemo {
    std::int64_t reused = 0;
};

ClippedParts clip_hidden_parts(const Scene&, const std::vector<const ImageAnalysis*>&, const ElementShapes&,
                               const std::vector<std::int64_t>&, const ElementGraph&, const std::vector<std::int32_t>&,
                               const MeshBuilder&, const ClipHiddenOptions&) {
    return {};
}

#else

// Per element, its last cut of each region (its blend-pass polygons, its
// opaque tile): what was cut (the region's texel polygons and the cuts
// tried, in Clipper's integers) and what came of it. A cut is a function
// of those alone for one element of one scene, so an equal one is reused.
// Its memory is bounded (kMaxBytes, about what the entries hold): past
// it, a cut not kept yet is made each time, as without a memo.
struct ClipMemo {
    struct Entry {
        bool valid = false, made = false;
        std::vector<Polygon> texel;
        std::vector<ClipperLib::Paths> cuts;
        ClippedPart part;
        std::size_t bytes = 0;
    };
    static constexpr std::size_t kMaxBytes = std::size_t(32) << 20;
    std::vector<Entry> entries; // [2 * element + region]
    std::size_t bytes = 0;      // held by the entries
    std::int64_t reused = 0;

    static std::size_t bytes_of(const std::vector<Polygon>& texel, const std::vector<ClipperLib::Paths>& cuts, const ClippedPart& part) {
        std::size_t b = sizeof(Entry);
        for (const Polygon& p : texel) b += p.size() * sizeof(Vec2);
        for (const ClipperLib::Paths& c : cuts)
            for (const ClipperLib::Path& p : c) b += p.size() * sizeof(ClipperLib::IntPoint);
        for (const Polygon& p : part.pieces) b += p.size() * sizeof(Vec2);
        for (const auto& t : part.triangles) b += t.size() * sizeof(std::uint32_t);
        return b;
    }
    // Keeps a cut made (in place of the entry's old one) while it fits.
    void keep(Entry& entry, const std::vector<Polygon>& texel, const std::vector<ClipperLib::Paths>& cuts, bool made, const ClippedPart& part) {
        bytes -= entry.bytes;
        entry = Entry{};
        const std::size_t b = bytes_of(texel, cuts, part);
        if (bytes + b > kMaxBytes) return;
        entry = {true, made, texel, cuts, part, b};
        bytes += b;
    }
};

namespace {

namespace cl = ClipperLib;

constexpr double kScale = 4294967296.0; // 2^32 per screen pixel: every float coordinate above 2^-9 px is exact
constexpr double kMaxCoordinate = 67108864.0; // 2^26 px: products stay inside Clipper's 128-bit range
constexpr double kPush = 1.0 / 64;      // outward push of cut vertices on B's outline, screen px
constexpr double kOnEdge = 1e-6;        // px: a cut vertex this close to an edge of B lies on it
constexpr std::size_t kMaxOccluders = 64; // per element: nearest first in graph order; more are ignored
// Least height of a cut piece's triangles on screen, px. GL moves each
// vertex by up to 1/512 px per coordinate and float rounding by under
// 2^-12 (screens under 8192 px): a triangle's height changes by under
// 0.0062 px, so one this high cannot turn over. A thinner one (three cut
// points nearly on a line, an exact triangulation's zero-area sliver) can,
// and then it and its neighbours cover pixel centres beside it twice.
constexpr double kMinHeight = 1.0 / 128;
// Most a cut triangle's longest side may be, in its heights. GL
// interpolates texture coordinates over a triangle from its three
// vertices as floats; a needle magnifies their rounding by its aspect, so
// a pixel centre a thousandth of a texel from a texel edge could sample
// the neighbouring texel, which overpaint's quad does not. That matters
// where pixel centres fall anywhere in a texel: elements GL does not snap
// exactly. Measured (a scratch search, 5000 random scenes of random
// shapes turned and scaled 0.3 .. 4, cut behind cover pieces): 4 differed
// without this limit, none with it. Elements that snap exactly have their
// pixel centres on a texel edge or at least 1/256 px from one, so they
// take a looser limit (corpus needles reach aspect 1400 uncut, exact
// vertices; cut, their vertices are rounded).
constexpr double kMaxAspect = 64, kMaxAspectSnapped = 1024;
double max_aspect(bool snapped) { return snapped ? kMaxAspectSnapped : kMaxAspect; }

// Screen position of texel point v of element e as GL gets it (float).
Vec2 screen_of(const Element& e, Vec2 v) {
    const Vec2 s = apply(e.transform, {v.x - e.rect.x, v.y - e.rect.y});
    return {double(float(s.x)), double(float(s.y))};
}

bool to_path(const Polygon& screen, cl::Path& out) {
    out.clear();
    for (const Vec2& p : screen) {
        if (!(std::abs(p.x) < kMaxCoordinate) || !(std::abs(p.y) < kMaxCoordinate)) return false;
        out.push_back({cl::cInt(std::llround(p.x * kScale)), cl::cInt(std::llround(p.y * kScale))});
    }
    return true;
}

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
    const Vec2 d = b - a;
    const double len2 = d.x * d.x + d.y * d.y;
    const double t = len2 > 0 ? std::clamp(((p.x - a.x) * d.x + (p.y - a.y) * d.y) / len2, 0.0, 1.0) : 0.0;
    return std::hypot(a.x + t * d.x - p.x, a.y + t * d.y - p.y);
}

// Strictly inside polygon q (either orientation), by crossings; points
// within kOnEdge of an edge count as not inside.
bool strictly_inside(Vec2 p, const Polygon& q) {
    bool in = false;
    const std::size_t n = q.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        if (distance_to_segment(p, q[j], q[i]) < kOnEdge) return false;
        if ((q[i].y > p.y) != (q[j].y > p.y) && p.x < (q[j].x - q[i].x) * (p.y - q[i].y) / (q[j].y - q[i].y) + q[i].x) in = !in;
    }
    return in;
}

// The occluder polygon shrunk by `margin`, checked: every vertex at least
// margin / 2 inside every edge of the convex original (else none: a
// polygon that vanishes or a join that overshoots is not used).
bool shrink(const Polygon& convex_screen, double margin, cl::Paths& out) {
    cl::Path path;
    if (convex_screen.size() < 3 || !to_path(convex_screen, path)) return false;
    cl::ClipperOffset offset(2.0);
    offset.AddPath(path, cl::jtMiter, cl::etClosedPolygon);
    cl::Paths shrunk;
    offset.Execute(shrunk, -margin * kScale);
    const double sign = signed_area(convex_screen) > 0 ? 1.0 : -1.0;
    const std::size_t n = convex_screen.size();
    for (const cl::Path& s : shrunk) {
        for (const cl::IntPoint& ip : s) {
            const Vec2 p{double(ip.X) / kScale, double(ip.Y) / kScale};
            for (std::size_t i = 0; i < n; ++i) {
                const Vec2 a = convex_screen[i], b = convex_screen[(i + 1) % n];
                const double len = std::hypot(b.x - a.x, b.y - a.y);
                if (len == 0) continue;
                // Positive signed area is clockwise with y down: the inside is to the right of a->b.
                if (sign * orient(a, b, p) / len < margin / 2) return false;
            }
        }
        out.push_back(s);
    }
    return !out.empty();
}

double triangle_perimeter(const std::vector<Vec2>& screen, const std::vector<std::uint32_t>& tris) {
    double sum = 0;
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const Vec2 a = screen[tris[t + std::size_t(k)]], b = screen[tris[t + std::size_t((k + 1) % 3)]];
            sum += std::hypot(b.x - a.x, b.y - a.y);
        }
    return sum;
}

struct Region {
    std::vector<Polygon> texel;  // B's polygons, texel space
    std::vector<Polygon> screen; // the same as GL gets them
};

// What is left of B: outlines, each with the holes inside it, and their
// triangles when triangulated whole (empty: not yet).
struct Group {
    std::vector<cl::Path> contours;
    std::vector<std::uint32_t> triangles;
};

double path_area(const cl::Path& path) { return std::abs(cl::Area(path)) / (kScale * kScale); }

// subject - cut as groups of an outline and its holes; false when Clipper fails.
bool difference(const cl::Paths& subject, const cl::Paths& cut, std::vector<Group>* groups, double* area) {
    cl::Clipper clipper;
    clipper.StrictlySimple(true);
    clipper.PreserveCollinear(true);
    clipper.AddPaths(subject, cl::ptSubject, true);
    clipper.AddPaths(cut, cl::ptClip, true);
    cl::PolyTree tree;
    if (!clipper.Execute(cl::ctDifference, tree, cl::pftNonZero, cl::pftNonZero)) return false;
    for (cl::PolyNode* node = tree.GetFirst(); node; node = node->GetNext()) {
        if (node->IsOpen() || node->IsHole()) continue;
        Group g;
        g.contours.push_back(node->Contour);
        *area += path_area(node->Contour);
        for (const cl::PolyNode* hole : node->Childs) {
            g.contours.push_back(hole->Contour);
            *area -= path_area(hole->Contour);
        }
        groups->push_back(std::move(g));
    }
    return true;
}

// Each group triangulated whole, on Clipper's exact grid; false when one
// cannot be (too many points, touching contours).
bool triangulate_groups(std::vector<Group>& groups, bool snapped) {
    std::vector<std::vector<GridPoint>> contours;
    for (Group& g : groups) {
        contours.clear();
        for (const cl::Path& c : g.contours) {
            contours.emplace_back();
            for (const cl::IntPoint& q : c) contours.back().push_back({q.X, q.Y});
        }
        g.triangles = triangulate_with_holes(contours, cl::cInt(kMinHeight * kScale), max_aspect(snapped));
        if (g.triangles.empty()) return false;
    }
    return true;
}

// The fallback when a region with holes cannot be triangulated whole: B
// cut into vertical strips at whole-pixel x through each hole. Strip edges
// run exactly on x = k (floats and GL keep whole numbers; B snaps
// exactly), 0.5 px from every pixel centre, so the strips tile B with no
// pixel drawn twice or lost although their vertices on x = k differ.
bool strip_groups(const cl::Paths& subject, const cl::Paths& cut, std::vector<Group>* groups, double* area) {
    std::vector<cl::cInt> splits;
    const cl::cInt far = cl::cInt(kMaxCoordinate * 2 * kScale);
    for (int round = 0; round < 8; ++round) {
        groups->clear();
        *area = 0;
        bool again = false;
        for (std::size_t k = 0; k <= splits.size(); ++k) {
            cl::Paths part = subject;
            if (!splits.empty()) {
                const cl::cInt lo = k == 0 ? -far : splits[k - 1], hi = k == splits.size() ? far : splits[k];
                cl::Clipper strip;
                strip.PreserveCollinear(true);
                strip.AddPaths(subject, cl::ptSubject, true);
                strip.AddPath(cl::Path{{lo, -far}, {hi, -far}, {hi, far}, {lo, far}}, cl::ptClip, true);
                part.clear();
                if (!strip.Execute(cl::ctIntersection, part, cl::pftNonZero, cl::pftNonZero)) return false;
            }
            std::vector<Group> pieces;
            if (!difference(part, cut, &pieces, area)) return false;
            for (Group& g : pieces) {
                for (std::size_t h = 1; h < g.contours.size(); ++h) {
                    cl::cInt lo = g.contours[h][0].X, hi = lo;
                    for (const cl::IntPoint& q : g.contours[h]) lo = std::min(lo, q.X), hi = std::max(hi, q.X);
                    const double x = std::floor((double(lo) + double(hi)) / 2 / kScale);
                    const cl::cInt at = cl::cInt(x * kScale), at2 = cl::cInt((x + 1) * kScale);
                    if (at > lo && at < hi) splits.push_back(at);
                    else if (at2 > lo && at2 < hi) splits.push_back(at2);
                    else return false;
                    again = true;
                }
                if (g.contours.size() == 1) groups->push_back(std::move(g));
            }
        }
        if (!again) return true;
        std::sort(splits.begin(), splits.end());
        splits.erase(std::unique(splits.begin(), splits.end()), splits.end());
    }
    return false;
}

// The texel point B draws at cut vertex `ip`: B's own vertex bit for bit,
// else the point pushed outward when on B's outline; false when the point
// cannot be used (see the head comment).
bool texel_point(const Element& e, const Region& region, const std::map<std::pair<cl::cInt, cl::cInt>, Vec2>& original,
                 const TexelMap& map, bool snapped, cl::IntPoint ip, Vec2* out) {
    auto it = original.find({ip.X, ip.Y});
    if (it != original.end()) {
        *out = it->second;
        return true;
    }
    Vec2 s{double(ip.X) / kScale, double(ip.Y) / kScale};
    // On B's outline: pushed outward, off B's polygons.
    bool pushed = false;
    for (std::size_t k = 0; k < region.screen.size() && !pushed; ++k) {
        const Polygon& q = region.screen[k];
        const std::size_t m = q.size();
        const double sign = signed_area(q) > 0 ? 1.0 : -1.0;
        for (std::size_t i = 0; i < m && !pushed; ++i) {
            const Vec2 a = q[i], c = q[(i + 1) % m];
            const double len = std::hypot(c.x - a.x, c.y - a.y);
            if (len == 0 || distance_to_segment(s, a, c) >= kOnEdge) continue;
            // Outward is to the left of a->c for a clockwise (positive) polygon, y down.
            const Vec2 normal{sign * (c.y - a.y) / len, -sign * (c.x - a.x) / len};
            s = s + kPush * normal;
            pushed = true;
        }
    }
    // A push that lands inside B (a reflex corner, another of its
    // polygons) could uncover a pixel: no cut for this element.
    if (pushed)
        for (const Polygon& q : region.screen)
            if (strictly_inside(s, q)) return false;
    Vec2 t{map.u0 + map.ux * s.x + map.uy * s.y, map.v0 + map.vx * s.x + map.vy * s.y};
    const double x0 = e.rect.x, x1 = double(e.rect.x) + e.rect.w, y0 = e.rect.y, y1 = double(e.rect.y) + e.rect.h;
    // Not snapped: cut vertices lie `margin` inside the rect, so a
    // point here outside it is a polygon the checks above missed.
    if (!snapped && !(t.x > x0 && t.x < x1 && t.y > y0 && t.y < y1)) return false;
    *out = {std::clamp(t.x, x0, x1), std::clamp(t.y, y0, y1)};
    return true;
}

// The group as B draws it (texel points, the contours' points in order),
// its triangles checked in texel space: none turns against the outline
// and their areas sum to the region's; and on screen, as GL gets them:
// none is thinner than kMinHeight or longer than max_aspect heights.
// `screen`: the piece's points as GL gets them. False when a check fails.
bool texel_piece(const Element& e, const Region& region, const std::map<std::pair<cl::cInt, cl::cInt>, Vec2>& original,
                 bool snapped, Group& g, Polygon* piece, Polygon* screen) {
    const TexelMap map = texel_map(e);
    double area = 0, outline_sign = 0;
    for (std::size_t c = 0; c < g.contours.size(); ++c) {
        Polygon contour;
        for (const cl::IntPoint& ip : g.contours[c]) {
            Vec2 t;
            if (!texel_point(e, region, original, map, snapped, ip, &t)) return false;
            contour.push_back(t);
        }
        const double a = signed_area(contour);
        if (c == 0) outline_sign = a < 0 ? -1.0 : 1.0;
        area += c == 0 ? std::abs(a) : -std::abs(a);
        piece->insert(piece->end(), contour.begin(), contour.end());
    }
    // A lone outline not triangulated whole (the strips): ear clipping,
    // exact on the texel grid only, hence the checks.
    if (g.triangles.empty() && g.contours.size() == 1) g.triangles = triangulate_polygon(*piece);
    for (const Vec2& t : *piece) screen->push_back(screen_of(e, t));
    double sum = 0;
    for (std::size_t t = 0; t + 2 < g.triangles.size(); t += 3) {
        const double o = orient((*piece)[g.triangles[t]], (*piece)[g.triangles[t + 1]], (*piece)[g.triangles[t + 2]]);
        if (outline_sign * o < 0) return false;
        sum += std::abs(o) / 2;
        const Vec2 a = (*screen)[g.triangles[t]], b = (*screen)[g.triangles[t + 1]], c = (*screen)[g.triangles[t + 2]];
        const double longest = std::max({std::hypot(b.x - a.x, b.y - a.y), std::hypot(c.x - b.x, c.y - b.y), std::hypot(a.x - c.x, a.y - c.y)});
        const double least = std::max(kMinHeight, longest / max_aspect(snapped));
        if (!(std::abs(orient(a, b, c)) >= least * longest)) return false;
    }
    return std::abs(sum - area) <= 1e-9 * std::max(1.0, sum);
}

// Cuts `region` of element b at `cut`; true (and *out) when it pays.
bool clip_region(const Scene& scene, std::uint32_t b, const Region& region, const cl::Paths& cut, const ClipHiddenOptions& options,
                 bool snapped, ClippedPart* out) {
    const Element& e = scene.elements[b];
    cl::Paths subject;
    std::map<std::pair<cl::cInt, cl::cInt>, Vec2> original;
    double old_triangles = 0, old_perimeter = 0, old_area = 0;
    for (std::size_t k = 0; k < region.texel.size(); ++k) {
        cl::Path path;
        if (!to_path(region.screen[k], path)) return false;
        for (std::size_t i = 0; i < path.size(); ++i) original[{path[i].X, path[i].Y}] = region.texel[k][i];
        const std::vector<std::uint32_t> tris = triangulate_polygon(region.texel[k]);
        old_triangles += double(tris.size() / 3);
        old_perimeter += triangle_perimeter(region.screen[k], tris);
        old_area += path_area(path);
        subject.push_back(std::move(path));
    }
    // What is left, triangulated whole (holes included: an occluder inside
    // B); else, for B snapped exactly, in strips without holes.
    std::vector<Group> groups;
    double new_area = 0;
    if (!difference(subject, cut, &groups, &new_area)) return false;
    if (!triangulate_groups(groups, snapped)) {
        bool holes = false;
        for (const Group& g : groups) holes = holes || g.contours.size() > 1;
        // Strips would end on the rect's outline, off GL's snapped lines.
        if (holes && (!snapped || !strip_groups(subject, cut, &groups, &new_area))) return false;
    }
    const double saved_pixels = old_area - new_area;
    if (!(saved_pixels > 0)) return false;
    ClippedPart part;
    double new_triangles = 0, new_perimeter = 0;
    for (Group& g : groups) {
        Polygon piece, screen;
        if (!texel_piece(e, region, original, snapped, g, &piece, &screen)) return false;
        if (g.triangles.empty()) continue;
        new_triangles += double(g.triangles.size() / 3);
        new_perimeter += triangle_perimeter(screen, g.triangles);
        part.pieces.push_back(std::move(piece));
        part.triangles.push_back(std::move(g.triangles));
    }
    const double gain = saved_pixels * options.fragment_cost - (new_triangles - old_triangles) * options.triangle_cost -
                        (new_perimeter - old_perimeter) * options.perimeter_cost;
    if (!(gain > 0)) return false;
    *out = std::move(part);
    return true;
}

bool boxes_overlap(const cl::Paths& a, const Polygon& b_screen) {
    double ax0 = INFINITY, ay0 = INFINITY, ax1 = -INFINITY, ay1 = -INFINITY;
    for (const cl::Path& p : a)
        for (const cl::IntPoint& q : p) {
            ax0 = std::min(ax0, double(q.X) / kScale), ax1 = std::max(ax1, double(q.X) / kScale);
            ay0 = std::min(ay0, double(q.Y) / kScale), ay1 = std::max(ay1, double(q.Y) / kScale);
        }
    double bx0 = INFINITY, by0 = INFINITY, bx1 = -INFINITY, by1 = -INFINITY;
    for (const Vec2& q : b_screen) bx0 = std::min(bx0, q.x), bx1 = std::max(bx1, q.x), by0 = std::min(by0, q.y), by1 = std::max(by1, q.y);
    return ax0 < bx1 && bx0 < ax1 && ay0 < by1 && by0 < ay1;
}

} // namespace

ClippedParts clip_hidden_parts(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses, const ElementShapes& shapes,
                               const std::vector<std::int64_t>& levels, const ElementGraph& graph,
                               const std::vector<std::int32_t>& keys, const MeshBuilder& builder,
                               const ClipHiddenOptions& options) {
    ClippedParts result;
    const std::size_t n = scene.elements.size();
    if (!options.enabled || !(options.margin > 0) || graph.size() != n || levels.size() != n) return result;
    const std::vector<std::vector<std::uint32_t>> front = graph.in_front();
    if (options.memo) options.memo->entries.resize(std::max(options.memo->entries.size(), 2 * n));
    // Each occluder's cut region, made once.
    std::vector<std::uint8_t> made(n, 0);
    std::vector<cl::Paths> cut_of(n);
    auto occluder = [&](std::uint32_t a) -> const cl::Paths& {
        if (made[a]) return cut_of[a];
        made[a] = 1;
        const Element& e = scene.elements[a];
        std::vector<Polygon> polys;
        if (shapes.opaque[a] == Shape::rect) polys.push_back(rect_polygon(e.rect));
        else if (shapes.opaque[a] == Shape::analysis && a < analyses.size() && analyses[a])
            for (const Polygon& p : analyses[a]->opaque) polys.push_back(builder.pull_inward(a, p));
        for (const Polygon& p : polys) {
            if (p.size() < 3) continue;
            Polygon s;
            for (const Vec2& v : p) s.push_back(screen_of(e, v));
            // No margin along the rect's sides of a pixel-aligned occluder
            // (side_margins): its polygon meets them exactly, on whole
            // pixels, as the rect does, so an element behind that shares a
            // side (a tile under a tile) keeps no thin rim along it.
            std::vector<double> d = shapes.opaque[a] == Shape::rect ? std::vector<double>(p.size(), pixel_aligned(scene, e) ? 0.0 : options.margin)
                                                                  : side_margins(scene, e, p, options.margin);
            cl::Path path;
            if (std::find(d.begin(), d.end(), 0.0) == d.end()) shrink(s, options.margin, cut_of[a]);
            else if (const Polygon moved = move_edges_inward(s, d); moved.size() >= 3 && to_path(moved, path)) cut_of[a].push_back(std::move(path));
        }
        return cut_of[a];
    };
    try {
        for (std::uint32_t b = 0; b < n; ++b) {
            const Element& e = scene.elements[b];
            const bool snapped = snaps_exactly(e.transform);
            const bool blend = shapes.blended[b] && shapes.boundary[b] != Shape::none && keys[b] >= 0;
            const bool opaque_tile = shapes.opaque[b] == Shape::rect && keys[b] >= 0;
            if (!blend && !opaque_tile) continue;
            // Both regions lie in the rect: occluders whose cut misses the rect are skipped.
            Polygon rect_screen;
            for (const Vec2& v : rect_polygon(e.rect)) rect_screen.push_back(screen_of(e, v));
            cl::Paths cut;
            std::size_t used = 0;
            // Its own opaque polygons too: drawn nearer (2k+2 against 2k+1),
            // they reject its own blend fragments under them.
            std::vector<std::uint32_t> occluders = front[b];
            if (blend && shapes.opaque[b] == Shape::analysis) occluders.insert(occluders.begin(), b);
            for (std::uint32_t a : occluders) {
                if ((a != b && levels[a] <= levels[b]) || shapes.opaque[a] == Shape::none || keys[a] < 0) continue;
                const cl::Paths& c = occluder(a);
                if (c.empty() || !boxes_overlap(c, rect_screen)) continue;
                cut.insert(cut.end(), c.begin(), c.end());
                if (++used == kMaxOccluders) break;
            }
            if (cut.empty()) continue;
            std::vector<cl::Paths> cuts; // to try in turn
            if (snapped) {
                cuts.push_back(std::move(cut));
            } else {
                // Kept `inset` inside the rect (see the head comment). Where
                // B reaches its rect, that leaves a band `inset` wide, whose
                // triangles are needles when it is long (kMaxAspect refuses
                // them): wider bands are tried before B is given up. A band
                // is B drawn as before, so any width is correct.
                double longest_side = 0;
                for (std::size_t k = 0; k < rect_screen.size(); ++k) {
                    const Vec2 u = rect_screen[k], v = rect_screen[(k + 1) % rect_screen.size()];
                    longest_side = std::max(longest_side, std::hypot(v.x - u.x, v.y - u.y));
                }
                double last = 0;
                for (double inset : {options.margin, 1.0, 4.0, longest_side / (kMaxAspect / 2)}) {
                    if (!(inset > last)) continue;
                    last = inset;
                    cl::Paths inner, kept;
                    if (!shrink(rect_screen, inset, inner)) break; // a wider one would vanish too
                    cl::Clipper clipper;
                    clipper.AddPaths(cut, cl::ptSubject, true);
                    clipper.AddPaths(inner, cl::ptClip, true);
                    if (!clipper.Execute(cl::ctIntersection, kept, cl::pftNonZero, cl::pftNonZero) || kept.empty()) break;
                    cuts.push_back(std::move(kept));
                }
            }
            auto region_of = [&](Shape shape) {
                Region r;
                if (shape == Shape::rect) r.texel.push_back(rect_polygon(e.rect));
                else if (shape == Shape::analysis && analyses[b]) r.texel = analyses[b]->boundary;
                for (const Polygon& p : r.texel) {
                    Polygon s;
                    for (const Vec2& v : p) s.push_back(screen_of(e, v));
                    r.screen.push_back(std::move(s));
                }
                return r;
            };
            // The first of the cuts that is made (region_of once per shape),
            // or the memo's when it cut the same region with the same cuts.
            auto first_cut = [&](Shape shape, std::size_t slot, std::unordered_map<std::uint32_t, ClippedPart>& into) {
                const Region region = region_of(shape);
                ClipMemo::Entry* memo = options.memo ? &options.memo->entries[2 * std::size_t(b) + slot] : nullptr;
                if (memo && memo->valid && memo->texel == region.texel && memo->cuts == cuts) {
                    ++options.memo->reused;
                    if (memo->made) into.emplace(b, memo->part), ++result.elements;
                    return;
                }
                ClippedPart part;
                bool made = false;
                for (const cl::Paths& c : cuts)
                    if ((made = clip_region(scene, b, region, c, options, snapped, &part))) break;
                if (memo) options.memo->keep(*memo, region.texel, cuts, made, part);
                if (made) into.emplace(b, std::move(part)), ++result.elements;
            };
            if (blend) first_cut(shapes.boundary[b], 0, result.blend);
            if (opaque_tile) first_cut(Shape::rect, 1, result.opaque);
        }
    } catch (...) {
        // Clipper throws only on coordinates past its range (checked before) or
        // when memory runs out: then nothing is clipped, which is always correct.
        return {};
    }
    return result;
}

#endif

void ClipMemoDelete::operator()(ClipMemo* memo) const { delete memo; }
std::unique_ptr<ClipMemo, ClipMemoDelete> make_clip_memo() { return std::unique_ptr<ClipMemo, ClipMemoDelete>(new ClipMemo); }
std::int64_t clip_memo_reused(const ClipMemo& memo) { return memo.reused; }

} // namespace depthcull::detail
