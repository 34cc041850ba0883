// Internal: the pieces of the Tiled (.tmx) reader.
//   tiled_data.cpp      layer data: CSV, XML, base64, zlib / gzip, chunks
//   tiled_tilesets.cpp  tilesets (inline and .tsx), tile rects, images, trans keys
//   tiled_layers.cpp    layers and objects -> elements, in Tiled's drawing order
//   tiled_map.cpp       tiled_map_from_bytes: the map, its viewport and culling
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <pugixml.hpp>

#include "depthcull/io.h"
#include "depthcull/limits.h"
#include "io/formats.h"

namespace depthcull::io::tiled {

// Bounds that keep a hostile map from making us allocate without bound
// (depthcull/limits.h; errors name them).
inline constexpr std::int64_t kMaxCells = limits::kMaxLayerCells;     // per tile layer, its chunks summed
inline constexpr std::int64_t kMaxElements = limits::kMaxMapElements; // per scene
inline constexpr int kMaxLayers = limits::kMaxLayers;
inline constexpr int kMaxTilesets = limits::kMaxTilesets;
inline constexpr std::size_t kMaxXmlBytes = limits::kMaxXmlBytes;     // after gunzip

// The gid flag bits (Tiled's TMX format): the rest is the global tile id.
inline constexpr std::uint32_t kFlipHorizontal = 0x80000000u;
inline constexpr std::uint32_t kFlipVertical = 0x40000000u;
inline constexpr std::uint32_t kFlipDiagonal = 0x20000000u;
inline constexpr std::uint32_t kRotateHex120 = 0x10000000u;
inline constexpr std::uint32_t kGidMask = 0x0fffffffu;

// ---- tiled_data.cpp

// An integer attribute; absent gives `fallback`, junk is an error.
int int_attr(pugi::xml_node node, const char* name, int fallback, const std::string& where);
// The same for wider integers (firstgid, map sizes checked by the caller),
// gids (32 bits, flip flags included) and numbers. pugixml's as_int,
// as_uint and as_double read the leading digits and give 0 for junk: a
// Tiled JSON "width": 1e300 became 1 and opacity="x" hid the layer.
long long llong_attr(pugi::xml_node node, const char* name, long long fallback, const std::string& where);
std::uint32_t gid_attr(pugi::xml_node node, const char* name, const std::string& where);
double double_attr(pugi::xml_node node, const char* name, double fallback, const std::string& where);
// visible="0" hides; absent or any other integer shows.
bool visible_attr(pugi::xml_node node, const std::string& where);

// The file's bytes, gunzipped when it starts with the gzip magic (so
// .tmx.gz and .tsx.gz need no special naming).
std::string read_maybe_gzipped(const std::string& path);
std::string maybe_gunzip(std::string_view bytes, const std::string& path);
// zlib or gzip stream -> bytes; more than max_bytes is an error (all
// members together). `gzip_members`: gzip members that follow the first are
// joined, as gunzip joins them (a whole .tmx.gz; layer data is one stream).
std::string inflate_bytes(std::string_view data, std::size_t max_bytes, const std::string& where, bool gzip_members = false);
std::vector<std::uint8_t> decode_base64(std::string_view text, const std::string& where);
// Which file `path` is, whatever its spelling ("./a.tx", "././a.tx", a
// symlink): "device:inode", or the path itself when it cannot be stat'ed
// (reading it then gives the error). Tilesets and templates are parsed
// once per file and map by it.
std::string file_identity(const std::string& path);

// A rectangle of cells, row-major; gid 0 is an empty cell.
struct CellGrid {
    int x0 = 0, y0 = 0, width = 0, height = 0;
    std::vector<std::uint32_t> gids;
};

// The <data> of a tile layer. `where` prefixes errors ("map.tmx: layer 'x'").
// Finite maps: a width x height grid. Infinite maps: the chunks merged into
// their bounding grid.
CellGrid read_layer_data(pugi::xml_node layer, int width, int height, bool infinite, const std::string& where);

// ---- tiled_json.cpp: Tiled's JSON forms as the TMX documents they stand for

// Whether the text is JSON (its first non-space character is '{'): Tiled
// files are told apart by content, so a .tmx naming a .json tileset works.
bool looks_like_json(std::string_view text);
// A JSON map (.tmj) -> <map>; a JSON tileset (.tsj) -> <tileset>; a JSON
// template (.tj) -> <template>. Errors name `path` and the place.
void json_map_to_xml(std::string_view text, const std::string& path, pugi::xml_document& doc);
void json_tileset_to_xml(std::string_view text, const std::string& path, pugi::xml_document& doc);
void json_template_to_xml(std::string_view text, const std::string& path, pugi::xml_document& doc);

// ---- tiled_tilesets.cpp

enum class Alignment { unspecified, topleft, top, topright, left, center, right, bottomleft, bottom, bottomright };

// One tile as drawn: which image, which texels.
struct Tile {
    int image = -1; // index into Scene::images; -1: no such tile
    Rect rect;
};

struct Tileset {
    std::uint32_t firstgid = 0;
    std::string name;
    std::string source; // the external .tsx as resolved (resolve_tsx); empty when inline
    int tile_width = 0, tile_height = 0; // the grid of an image tileset
    double offset_x = 0, offset_y = 0;   // <tileoffset>
    Alignment alignment = Alignment::unspecified;
    bool render_grid_size = false;       // tilerendersize="grid": tiles scaled to the map's grid
    bool preserve_aspect = false;        // ... with fillmode="preserve-aspect-fit": uniformly, centred in the cell
    // Tiles by local id. An image tileset's grid is computed, not stored (a
    // 16384x16384 image of 1x1 tiles would be a table of 5 GB); tiles named
    // by <tile id> (image collections, animations resolved to their first
    // frame) are sparse, so id 16777215 costs one entry.
    int image = -1; // the image of an image tileset, cut in columns x rows
    int columns = 0, rows = 0, margin = 0, spacing = 0;
    struct Tables {
        std::map<std::uint32_t, Tile> named;
        // Animated tiles by local id: every frame's tile and duration (ms);
        // the tile itself (in `named`) is its first frame.
        std::map<std::uint32_t, std::vector<std::pair<Tile, int>>> animations;
        // Animated tiles drawn otherwise than their file says, by local id:
        // what was done (frames naming tiles the tileset lacks are left
        // out; a tile left with none, or animated by The Mana World's
        // animation-frameN properties, stays still). A map that shows the
        // tile warns, --strict refuses.
        std::map<std::uint32_t, std::string> animation_warnings;
    };
    // Shared by every <tileset> naming the same file: it is parsed once
    // and held once, however many firstgids name it.
    std::shared_ptr<const Tables> tables = std::make_shared<const Tables>();
    std::uint32_t tile_count() const; // one past the largest local id
    Tile tile(std::uint32_t local) const; // image -1: no such tile
};

// Images shared by every tileset of the map: one SceneImage per distinct
// (file, trans key). Sizes are read through `files` when given
// (LoadOptions::image_files).
class ImageTable {
public:
    explicit ImageTable(std::vector<SceneImage>& images, ImageFiles* files = nullptr) : images_(images), files_(files) {}
    // `source` is the <image source> attribute, relative to `base_dir`.
    int add(const std::string& base_dir, const std::string& source, const std::string& trans, const std::string& where);
    // A solid-colour image (SceneImage::has_fill): the map's background.
    int add_fill(std::uint32_t rgb);
    int width(int index) const { return images_[std::size_t(index)].width; }
    int height(int index) const { return images_[std::size_t(index)].height; }

private:
    std::vector<SceneImage>& images_;
    ImageFiles* files_;
    std::map<std::string, int> by_key_;
    std::set<std::string> ids_;
};

// An external tileset's path: `source` relative to `base_dir`, or its
// gzipped twin when only that exists (Debian gzips example tilesets).
std::string resolve_tsx(const std::string& base_dir, const std::string& source);

// An external tileset (.tsx, gzipped or not) from its bytes; `tsx` names
// it and resolves its images.
Tileset tileset_from_bytes(std::string_view bytes, const std::string& tsx, std::uint32_t firstgid, ImageTable& images);

// All <tileset> children of the map, sorted by firstgid.
std::vector<Tileset> read_tilesets(pugi::xml_node map, const std::string& map_path, ImageTable& images);

// The tileset and local tile of a gid (flags masked off); throws when the
// gid names no tile.
struct TileRef {
    const Tileset* tileset = nullptr;
    Tile tile;
};
TileRef find_tile(const std::vector<Tileset>& tilesets, std::uint32_t gid, const std::string& where);


// ---- tiled_layers.cpp

// staggered maps are hexagonal ones with hexsidelength 0, as in Tiled.
enum class Orientation { orthogonal, isometric, hexagonal };
enum class RenderOrder { right_down, right_up, left_down, left_up };

struct MapInfo {
    std::string where; // the map's path, for errors
    Orientation orientation = Orientation::orthogonal;
    RenderOrder render_order = RenderOrder::right_down;
    int width = 0, height = 0, tile_width = 0, tile_height = 0;
    bool infinite = false;
    // hexagonal / staggered: Tiled's HexagonalRenderer parameters
    bool stagger_x = false;    // staggeraxis="x"
    bool stagger_even = false; // staggerindex="even"
    int hex_side = 0;          // hexsidelength (0 for staggered maps)
    bool hex_rotation = false; // orientation="hexagonal": gid bits 29 / 28 turn tiles 60 / 120 degrees
    double parallax_origin_x = 0, parallax_origin_y = 0; // parallaxoriginx / y
};

// Tiled colours: "#AARRGGBB" or "#RRGGBB" (the '#' optional), rgba 0..1.
std::array<double, 4> parse_color(const std::string& text, const std::string& where);

// Top-left corner on screen of cell (col, row) of a hexagonal or staggered
// map (Tiled's HexagonalRenderer::tileToScreenCoords).
Vec2 hex_cell_top_left(const MapInfo& info, int col, int row);

// Layer state inherited through groups.
struct LayerState {
    double offset_x = 0, offset_y = 0;
    double opacity = 1;
    std::array<double, 4> tint{1, 1, 1, 1}; // Tiled's effective tint colour, rgba 0..1 (product over groups)
    double parallax_x = 1, parallax_y = 1;  // effective parallax factor (product over groups)
};

struct Template; // tiled_layers.cpp

struct Emitter {
    const MapInfo& info;
    const std::vector<Tileset>& tilesets;
    ImageTable& images;
    const Viewport* cull = nullptr; // drop elements that miss it
    Scene& scene;
    std::int64_t cells = 0; // tile-layer cells read so far (limits::kMaxMapCells)
    const LoadOptions* options = nullptr; // warnings, notes, strict
    std::set<std::string> warned;         // one line per (place, feature)
    std::map<std::pair<const Tileset*, std::uint32_t>, int> animation_index; // into Scene::animations
    // Templates, each file parsed once per map: by the spelling objects use,
    // and by file_identity, so "./a.tx" and "././a.tx" share one document.
    std::map<std::string, std::shared_ptr<const Template>> templates_by_source, templates_by_file;
    // Estimated bytes of the parsed documents held (the map's, its
    // templates'): within limits::kMaxDocumentBytes together.
    std::uint64_t documents = 0;
    // Layers LoadOptions::insert_at named that were met (each must be).
    std::set<std::string> insert_at_found;
};

// The Scene::animations index of a tile's animation, or -1 when it has
// none (or frames of different sizes, which is warned about).
int animation_of(Emitter& out, const Tileset& tileset, std::uint32_t local, const std::string& where);

// One warning line naming the place and the feature (Error with
// LoadOptions::strict); each distinct line once per map.
void warn(Emitter& out, const std::string& line);
void note(Emitter& out, const std::string& line);

// Walks the layers under `parent` (groups recursively, at most
// limits::kMaxNestingDepth deep) in Tiled's drawing order and appends
// their visible tiles to the scene.
void emit_layers(pugi::xml_node parent, const LayerState& state, Emitter& out, int depth = 0);

// Screen bounding box of an element: [x0, x1) x [y0, y1).
Box element_bounds(const Element& element);

} // namespace depthcull::io::tiled
