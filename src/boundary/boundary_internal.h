// Internals of the boundary stage (paper 2.1), shared by its files.
//
// Everything here works on an integer *cell grid*: with Filter::nearest a
// cell is a texel square; with Filter::linear the grid is doubled (cells are
// half texels) so that a texel square grown by half a texel is a union of
// cells and polygon vertices on the half-texel grid are integers. Integer
// vertices keep every predicate exact: coordinates stay below 2^16, so all
// cross products fit easily in 64 bits.
//
// The occupied cells are stored as runs per row (the "row spans" that make
// IsLineEmpty cost one binary search per row instead of a pixel scan).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "depthcull/analyze.h"

namespace depthcull::boundary {

struct Pt {
    std::int64_t x = 0, y = 0;
    friend bool operator==(const Pt&, const Pt&) = default;
};
using IPolygon = std::vector<Pt>;

inline std::int64_t cross(Pt a, Pt b) { return a.x * b.y - a.y * b.x; }
inline Pt operator-(Pt a, Pt b) { return {a.x - b.x, a.y - b.y}; }
inline Pt operator+(Pt a, Pt b) { return {a.x + b.x, a.y + b.y}; }
// > 0 when a -> b -> c turns clockwise with y down (c on the interior side
// of a directed edge a -> b of a clockwise polygon).
inline std::int64_t orient(Pt a, Pt b, Pt c) { return cross(b - a, c - a); }


// Twice the signed area; positive for clockwise (y down).
std::int64_t twice_area(const IPolygon& p);

// Closed box of allowed vertex positions (the rect, or a part's box).
struct Bounds {
    std::int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool contains(Pt p) const { return p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1; }
};

struct Run {
    int x0 = 0, x1 = 0; // cells [x0, x1) of one row
};

// Occupied cells of a width x height grid.
class CellGrid {
public:
    CellGrid() = default;
    CellGrid(int width, int height, std::vector<std::vector<Run>> rows);

    int width() const { return width_; }
    int height() const { return height_; }
    bool empty() const { return cells_ == 0; }
    std::int64_t cells() const { return cells_; }
    Bounds box() const { return box_; } // bounding box of the occupied cells

    bool occupied(std::int64_t x, std::int64_t y) const;
    // Any occupied cell in row y with x0 <= x < x1.
    bool any_in_row(std::int64_t y, std::int64_t x0, std::int64_t x1) const;
    const Run* row_begin(int y) const { return runs_.data() + row_start_[std::size_t(y)]; }
    const Run* row_end(int y) const { return runs_.data() + row_start_[std::size_t(y) + 1]; }

    // Sound IsLineEmpty (paper 2.1.1, errata): true when the closed segment
    // ab meets no point of the interior of the union of occupied cells. A
    // segment may run along the outline of the texels, but not between two
    // occupied cells that share a side, since that would separate them.
    bool segment_clear(Pt a, Pt b) const;

private:
    bool both_rows_in_range(std::int64_t ya, std::int64_t yb, std::int64_t x0, std::int64_t x1) const;

    int width_ = 0, height_ = 0;
    std::vector<std::uint32_t> row_start_;
    std::vector<Run> runs_;
    std::int64_t cells_ = 0;
    Bounds box_;
};

// The cells of rect in image that the polygon must contain: texel squares
// (nearest) or texel squares grown by half a texel and clipped to the rect,
// on the doubled grid (linear). scale() is 1 or 2 respectively.
CellGrid make_cell_grid(ImageView image, Rect rect, Filter filter);
inline int grid_scale(Filter filter) { return filter == Filter::linear ? 2 : 1; }

// ---- Polygon predicates (containment_check.cpp)

// Removes repeated vertices and vertices on a straight angle or a
// zero-width spike (orientation 0), which change no area.
void remove_degenerate_vertices(IPolygon& p);
bool is_simple(const IPolygon& p);
// Point (px/2, py/2) strictly inside p (not on its boundary).
bool strictly_inside_doubled(const IPolygon& p, std::int64_t px, std::int64_t py);

// The exact acceptance test for a candidate polygon derived from `old`,
// which contains every occupied cell. On success `candidate` is cleaned of
// degenerate vertices and is simple, clockwise, inside `bounds`, has at most
// max_vertices vertices and contains every occupied cell.
bool accept_candidate(const CellGrid& grid, const Bounds& bounds, int max_vertices, const IPolygon& old,
                      IPolygon& candidate);

// Every occupied cell inside p (exact; used as the final safety net).
bool contains_all_cells(const CellGrid& grid, const IPolygon& p);

// ---- The steps of paper 2.1

// A candidate polygon and its twice-area, from one of the moves.
struct Candidate {
    IPolygon polygon;
    std::int64_t area2 = 0;
};

// Rounds the point base + num/den * dir to a grid point on the outer side
// (orient <= 0) of the directed line a -> b, closest to the line.
Pt round_outward(Pt a, Pt b, Pt base, Pt dir, std::int64_t num, std::int64_t den);

// Paper 2.1.1: candidates from cutting the corner at vertex i.
void cut_boundary_corner(const CellGrid& grid, const Bounds& bounds, const IPolygon& p, int i,
                         std::vector<Candidate>& out);
// Paper 2.1.2: candidates from inserting a vertex on edge (i, i+1).
void insert_boundary_vertex(const CellGrid& grid, const Bounds& bounds, const IPolygon& p, int i,
                            std::vector<Candidate>& out);
// Paper 2.1.3: polygons with vertex i removed by cutting a transparent
// corner (any of the three triangles); appended without checking.
void remove_transparent_corner(const IPolygon& p, int i, std::vector<Candidate>& out);

// Beyond the paper: the convex hull of the occupied cells (clockwise), and
// that hull reduced to at most max_vertices vertices inside `bounds`
// (empty when that is impossible).
IPolygon convex_hull(const CellGrid& grid);
IPolygon reduced_convex_hull(const CellGrid& grid, const Bounds& bounds, int max_vertices);

// Paper 2.1: the boundary polygon of the occupied cells of `grid`, with
// vertices in `bounds`.
IPolygon generate_boundary_polygon(const CellGrid& grid, const Bounds& bounds, int max_vertices);

} // namespace depthcull::boundary
