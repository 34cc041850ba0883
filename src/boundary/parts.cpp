// Disjoint parts (beyond the paper: its section 4, caveat 1) and the public
// entry point generate_boundary_polygons.
//
// The paper fits one polygon per image, and notes that an image with
// separate islands (two circles) is fitted badly. We group the islands into
// a few parts whose bounding boxes neither overlap nor touch, fit each part
// inside its own box (so the polygons cannot overlap or touch: a pixel
// drawn twice would change the look under blending), and keep the split
// only when it covers clearly less area than one polygon.
#include <algorithm>
#include <numeric>

#include "boundary/boundary_internal.h"

namespace depthcull {

namespace boundary {

namespace {

constexpr std::size_t kMaxComponents = 512; // more islands than this: noise, fit one polygon
constexpr std::size_t kMaxParts = 4;        // each part costs a polygon's triangles
constexpr std::int64_t kMinPartTexels = 16; // specks join their nearest part

struct Part {
    Bounds box;
    std::int64_t cells = 0;
    std::vector<std::size_t> runs; // global run indices
};

std::size_t find(std::vector<std::size_t>& parent, std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

bool boxes_touch(const Bounds& a, const Bounds& b) {
    return a.x0 <= b.x1 && b.x0 <= a.x1 && a.y0 <= b.y1 && b.y0 <= a.y1;
}

std::int64_t box_gap(const Bounds& a, const Bounds& b) {
    std::int64_t gx = std::max<std::int64_t>({0, a.x0 - b.x1, b.x0 - a.x1});
    std::int64_t gy = std::max<std::int64_t>({0, a.y0 - b.y1, b.y0 - a.y1});
    return std::max(gx, gy);
}

void absorb(Part& into, Part& from) {
    into.box = {std::min(into.box.x0, from.box.x0), std::min(into.box.y0, from.box.y0),
                std::max(into.box.x1, from.box.x1), std::max(into.box.y1, from.box.y1)};
    into.cells += from.cells;
    into.runs.insert(into.runs.end(), from.runs.begin(), from.runs.end());
    from.runs.clear();
}

// Merges parts whose boxes touch until none do. A pass merges everything
// it can into each part; another pass runs only if anything grew.
void merge_touching(std::vector<Part>& parts) {
    for (bool merged = true; merged;) {
        merged = false;
        for (std::size_t i = 0; i < parts.size(); ++i)
            for (std::size_t j = i + 1; j < parts.size();) {
                if (boxes_touch(parts[i].box, parts[j].box)) {
                    absorb(parts[i], parts[j]);
                    parts.erase(parts.begin() + std::ptrdiff_t(j));
                    merged = true;
                } else {
                    ++j;
                }
            }
    }
}

// Islands of 8-connected runs, grouped into at most kMaxParts parts with
// pairwise separated boxes. Deterministic: everything follows run order.
std::vector<Part> find_parts(const CellGrid& grid, std::int64_t min_cells) {
    const Run* base = grid.row_begin(0);
    const std::size_t total = std::size_t(grid.row_end(grid.height() - 1) - base);
    std::vector<std::size_t> parent(total);
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    for (int y = 0; y + 1 < grid.height(); ++y) {
        const Run *a = grid.row_begin(y), *ae = grid.row_end(y);
        const Run *b = grid.row_begin(y + 1), *be = grid.row_end(y + 1);
        while (a != ae && b != be) {
            if (a->x0 <= b->x1 && b->x0 <= a->x1) // overlap or diagonal contact
                parent[find(parent, std::size_t(a - base))] = find(parent, std::size_t(b - base));
            if (a->x1 < b->x1) ++a;
            else ++b;
        }
    }
    std::vector<Part> parts;
    std::vector<std::size_t> index(total, total);
    for (int y = 0; y < grid.height(); ++y)
        for (const Run* r = grid.row_begin(y); r != grid.row_end(y); ++r) {
            std::size_t root = find(parent, std::size_t(r - base));
            if (index[root] == total) {
                if (parts.size() == kMaxComponents) return {};
                index[root] = parts.size();
                parts.push_back({{r->x0, y, r->x1, y + 1}, 0, {}});
            }
            Part& p = parts[index[root]];
            p.box = {std::min<std::int64_t>(p.box.x0, r->x0), std::min<std::int64_t>(p.box.y0, y),
                     std::max<std::int64_t>(p.box.x1, r->x1), std::max<std::int64_t>(p.box.y1, y + 1)};
            p.cells += r->x1 - r->x0;
            p.runs.push_back(std::size_t(r - base));
        }
    merge_touching(parts);
    // Specks and surplus parts join the part whose box is nearest.
    while (parts.size() > 1) {
        std::size_t smallest = 0;
        for (std::size_t i = 1; i < parts.size(); ++i)
            if (parts[i].cells < parts[smallest].cells) smallest = i;
        if (parts.size() <= kMaxParts && parts[smallest].cells >= min_cells) break;
        std::size_t nearest = smallest == 0 ? 1 : 0;
        for (std::size_t i = 0; i < parts.size(); ++i)
            if (i != smallest && box_gap(parts[i].box, parts[smallest].box) < box_gap(parts[nearest].box, parts[smallest].box))
                nearest = i;
        absorb(parts[nearest], parts[smallest]);
        parts.erase(parts.begin() + std::ptrdiff_t(smallest));
        merge_touching(parts);
    }
    return parts;
}

CellGrid part_grid(const CellGrid& grid, const Part& part) {
    std::vector<std::vector<Run>> rows(std::size_t(grid.height()));
    const Run* base = grid.row_begin(0);
    std::vector<std::size_t> runs = part.runs;
    std::sort(runs.begin(), runs.end()); // row order, then x order
    std::size_t y = 0;
    for (std::size_t r : runs) {
        while (base + r >= grid.row_end(int(y))) ++y;
        rows[y].push_back(base[r]);
    }
    return CellGrid(grid.width(), grid.height(), std::move(rows));
}

IPolygon box_polygon(const Bounds& b) { return {{b.x0, b.y0}, {b.x1, b.y0}, {b.x1, b.y1}, {b.x0, b.y1}}; }

// The paper's polygon, with the exact check as a last line of defence: should
// a move ever slip through, the part's box is always a correct answer.
IPolygon fit(const CellGrid& grid, const Bounds& bounds, int max_vertices) {
    IPolygon p = generate_boundary_polygon(grid, bounds, max_vertices);
    bool ok = p.size() >= 3 && is_simple(p) && twice_area(p) > 0 && contains_all_cells(grid, p);
    for (Pt v : p) ok = ok && bounds.contains(v);
    return ok ? p : box_polygon(grid.box());
}

} // namespace

} // namespace boundary

std::vector<Polygon> generate_boundary_polygons(ImageView image, Rect rect, const BoundaryOptions& options, Filter filter) {
    using namespace boundary;
    using boundary::is_simple;
    if (rect.empty() || !image.contains(rect)) return {};
    const CellGrid grid = make_cell_grid(image, rect, filter);
    if (grid.empty()) return {};
    // Four is the least budget that always fits: content in all four
    // corners of its rect leaves no containing triangle inside the rect.
    const int max_vertices = std::max(kMinBoundaryVertices, options.max_vertices);
    const Bounds whole{0, 0, grid.width(), grid.height()};

    std::vector<IPolygon> result{fit(grid, whole, max_vertices)};
    if (options.split_parts) {
        const std::int64_t scale2 = std::int64_t(grid_scale(filter)) * grid_scale(filter);
        std::vector<Part> parts = find_parts(grid, kMinPartTexels * scale2);
        if (parts.size() > 1) {
            std::vector<IPolygon> split;
            std::int64_t split_area2 = 0;
            for (const Part& part : parts) {
                split.push_back(fit(part_grid(grid, part), part.box, max_vertices));
                split_area2 += twice_area(split.back());
            }
            // Each extra polygon costs triangles and a draw's worth of setup:
            // split only for a saving of at least 5%.
            if (split_area2 * 20 <= twice_area(result[0]) * 19) result = std::move(split);
        }
    }

    const double scale = grid_scale(filter);
    std::vector<Polygon> out;
    for (const IPolygon& p : result) {
        Polygon q;
        for (Pt v : p) q.push_back({rect.x + double(v.x) / scale, rect.y + double(v.y) / scale});
        out.push_back(std::move(q));
    }
    return out;
}

} // namespace depthcull
