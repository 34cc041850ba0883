// depthcull: file formats and files. Everything here may do I/O and throws
// depthcull::Error (depthcull/error.h), whose message is one line naming
// the file and what is wrong with it ("scene.json: element 3: unknown
// image id \"rok\""). It is the only exception that leaves these
// functions: parser errors, std::bad_alloc and the like are mapped to it.
// The limits on what is read are in depthcull/limits.h.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>

#include "depthcull/error.h"
#include "depthcull/image.h"
#include "depthcull/limits.h"
#include "depthcull/scene.h"

namespace depthcull::io {

// A library exception's text without nlohmann's "[json.exception.x.n] ".
inline std::string exception_text(const std::exception& e) {
    std::string message = e.what();
    if (message.compare(0, 16, "[json.exception.") == 0)
        if (auto end = message.find("] "); end != std::string::npos) message = message.substr(end + 2);
    return message;
}

// fn(), with every exception that is not ours (std::bad_alloc, a library's
// own types) turned into an Error naming `path`: the library throws
// only its documented types.
template <class F>
auto guarded(const std::string& path, F&& fn) -> decltype(fn()) {
    try {
        return fn();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        // Within every limit (README, "Limits") yet beyond this machine: the
        // limits that bound memory are named so the user knows what held.
        throw Error(path + ": out of memory (the limits allow " + std::to_string(limits::kMaxDecodedBytes >> 20) +
                    " MiB of decoded images, kMaxDecodedBytes, and " + std::to_string(kMaxAnalysisBytes >> 20) +
                    " MiB of analysis memory, kMaxAnalysisBytes)");
    } catch (const std::filesystem::filesystem_error& e) {
        throw Error(path + ": " + e.code().message() + " (" + e.path1().string() + ")");
    } catch (const std::exception& e) {
        throw Error(path + ": " + exception_text(e));
    }
}

// An Error when JSON `text` nests arrays / objects deeper than
// limits::kMaxNestingDepth (nlohmann's parser copes, but copying, dumping
// and our walks of the document recurse), or when its parsed document
// would take more than limits::kMaxDocumentBytes of memory, estimated in
// one pass before anything is allocated: a small file of "[]," takes
// about 16 times its size once parsed, and nlohmann's destructor
// terminates the process when it runs out of memory freeing a partial one
// (json_checks.cpp). Every JSON reader calls it before parsing.
void check_json_document(std::string_view text, const std::string& path);
// An Error "<path>: not valid JSON at line L, column C (byte B): <what>"
// for an exception nlohmann's parse threw over `text` (B counted from 0):
// the one form of every JSON reader, quoting none of the file's bytes.
[[noreturn]] void throw_json_error(const std::exception& e, std::string_view text, const std::string& path);

// Colour keys (SceneImage::trans) as files write them: "rrggbb".
std::string color_key_text(std::uint32_t rgb);

// PNG of any colour type libpng reads (grey, palette with tRNS, 16-bit,
// RGB, RGBA), converted to RGBA8. Rejects images over kMaxImageSide /
// kMaxImageTexels.
Image read_png(const std::string& path);
// Any image we read, told by its content (not its name): PNG, JPEG (no
// alpha: every texel fully opaque) or WebP (lossy or lossless, with or
// without alpha), as RGBA8; the same limits as read_png. PNG samples are
// the file's own (no gamma conversion; 16 bits rounded to 8), as WebGL,
// stb_image and Tiled read them. Files engines load that we read by an
// assumption add one line each to `warnings` (when given) naming the file
// and the assumption: a CMYK JPEG (converted as (1-C)(1-K), no colour
// profile), an animated WebP (its first frame).
Image read_image(const std::string& path, std::vector<std::string>* warnings = nullptr);
Image decode_image(const void* data, std::size_t size, const std::string& name, std::vector<std::string>* warnings = nullptr);
class ImageFiles;
// An image's width and height from its header, without decoding (so a
// size can be checked before the decode allocates): for any image
// read_image reads, told by content; the file kept in `files` when given.
// Otherwise a PNG's header alone is read (JPEG and WebP are read whole:
// their sizes lie after variable-length segments).
void image_size(const std::string& path, int* width, int* height, ImageFiles* files = nullptr); // image_formats.cpp
// Image files as a scene load read them, kept for the decode that follows
// (pipeline::prepare_scene): the loaders take each image's size from these
// bytes and the pipeline decodes the same bytes, so each file is opened and
// read once per run. Without one (LoadOptions::image_files null) a loader
// reads only each image's header (import, which decodes nothing).
class ImageFiles {
public:
    explicit ImageFiles(std::uint64_t budget = limits::kMaxKeptImageBytes) : budget_(budget) {}
    // The file's bytes, read whole on first use (read_file's checks) and
    // kept; null, reading nothing, once keeping them would pass the budget
    // (all files together): the caller reads the file as without
    // ImageFiles, and its decode reads it again.
    const std::string* read(const std::string& path);
    // Bytes kept before, or null. Const: safe from many threads at once.
    const std::string* find(const std::string& path) const;
    void clear() {
        files_.clear();
        kept_ = 0;
    }

private:
    std::uint64_t budget_;
    std::uint64_t kept_ = 0;
    std::unordered_map<std::string, std::string> files_;
};
// The pixels a SceneImage stands for: its file decoded (from `files` when
// they hold it), its colour key (SceneImage::trans) applied.
Image read_scene_image(const SceneImage& image, const ImageFiles* files = nullptr, std::vector<std::string>* warnings = nullptr);
// Texels of colour 0xRRGGBB become fully transparent (alpha 0).
void apply_color_key(Image& image, std::uint32_t rgb);
Image decode_png(const void* data, std::size_t size, const std::string& name);
std::string encode_png(ImageView image);
void write_png(const std::string& path, ImageView image); // atomic

// A regular file of at most limits::kMaxFileBytes (devices and FIFOs are
// refused, so /dev/zero cannot be read without end).
std::string read_file(const std::string& path);
// Writes to a temporary file beside `path` (".NAME.tmp.<pid>.<n>"), then
// renames it over `path`, so a reader never sees a half-written file and a
// failure leaves none; temporaries that a killed writer left there (whose
// pid is gone) are removed first. A symlink is followed and its target
// replaced; a device, FIFO or /dev/stdout is written in place; a directory
// is refused (depthcull/staged_files.h).
void write_file_atomic(const std::string& path, std::string_view bytes);
// Bytes handed over in pieces, in order (a large output is written as it is
// made, never held whole).
using WriteBytes = std::function<void(std::string_view)>;
// The same, for bytes `produce` hands to its writer in pieces: they go into
// the temporary file as they come; if `produce` throws, the temporary is
// removed and the error passes on, so `path` is never half-written.
void write_file_atomic(const std::string& path, const std::function<void(const WriteBytes&)>& produce);
// Whether two paths name one file: the same inode when both exist, else
// the same canonical path (an output not yet written vs another). Never
// true for "" or "-" (stdout).
bool same_file(const std::string& a, const std::string& b);
// Whether `text` is valid UTF-8 (JSON's encoding; paths and names from
// file systems and XML may hold other bytes).
bool valid_utf8(std::string_view text);

// Scene loading, by extension: .json (our scene format), .tmx / .tmx.gz
// (Tiled); a PNG or a directory of PNGs (recursive) is a contact sheet: each
// image once, in rows of up to 1024 px, 4 px apart, in path order. Image sizes are filled in; images are not kept.
// Tiled maps (src/io/tiled_map.cpp): orthogonal, isometric, staggered and
// hexagonal; every layer encoding; external and gzipped tilesets; tile
// objects and templates; drawn in Tiled's order. JSON maps, tilesets and
// templates (.tmj, .tsj, .tj; a .json is told by content). Animated tiles
// are drawn at their first frame and recorded in Scene::animations. A tileset image's trans
// colour key is kept on its SceneImage (has_trans, trans) and applied at
// decode (read_scene_image); loading writes no file.
struct LoadOptions {
    bool has_viewport = false; // --viewport x,y,w,h
    Viewport viewport;
    // What a reader approximates or leaves out (a Tiled feature we do not
    // draw), one line each naming the file, the layer and the feature:
    // passed to `warning` (nothing when empty), or an Error when
    // `strict`. Notes (`note`) say how to read the result (parallax layers
    // placed for this camera only) and never fail.
    std::function<void(const std::string&)> warning, note;
    bool strict = false;
    // Where the loaders keep the image files they read (see ImageFiles);
    // null: they read only the headers.
    ImageFiles* image_files = nullptr;
    // More insertion points for moving sprites (Scene::insertion_points;
    // the CLI's --insert-at): in a Tiled map, layer names (the point goes
    // after the layer's elements, as each object layer's does); in other
    // scenes, element indices. One that names nothing is an Error.
    std::vector<std::string> insert_at;
    // When given, every file the load read besides the images is appended
    // (the scene, external tilesets, object templates, atlases): the CLI
    // refuses an output over any of them, as over the images.
    std::vector<std::string>* documents = nullptr;
};
Scene read_scene(const std::string& path, const LoadOptions& options = {});
// Warning lines (a reader's or decode_image's) as LoadOptions asks: each
// distinct line once, in order, to options.warning; with options.strict
// an Error "<first line> (--strict)" instead.
void report_warnings(const std::vector<std::string>& lines, const LoadOptions& options);

// Our scene JSON format, as read_scene reads it: viewport, filter, images
// {id, path}, elements {image, rect, transform, color, blend}. Image paths
// are written relative to the directory of `output_path` (the cwd when it
// is empty or "-") when they can be, so the scene moves with its art.
std::string scene_to_json_text(const Scene& scene, const std::string& output_path);
void write_scene_json(const std::string& path, const Scene& scene); // atomic

// ---- Atlases: TexturePacker JSON (hash, array, and the multipack form
// {"textures": [{image, size, frames}, ...]} Phaser 3 reads) and cocos2d-x
// .plist sprite frames (formats 2 and 3), told by content

struct AtlasFrame {
    std::string name;
    Rect frame;              // texels in the atlas page; for a rotated frame, as stored (w and h swapped)
    bool rotated = false;    // stored rotated 90 degrees clockwise in the page
    bool trimmed = false;
    Rect sprite_source;      // spriteSourceSize: where the trimmed frame sits in the untrimmed sprite
    int source_w = 0, source_h = 0; // sourceSize: the untrimmed sprite
    int page = 0;            // index into Atlas::pages
};

struct AtlasPage {
    std::string image_path;  // resolved relative to the atlas file
    int width = 0, height = 0; // as the atlas states it (0: not stated)
};

enum class AtlasForm { json_hash, json_array, json_multipack, cocos2d_plist };

struct Atlas {
    std::string path;        // the .json or .plist
    AtlasForm form = AtlasForm::json_hash;
    int plist_format = 0;    // cocos2d_plist: metadata.format (2 or 3)
    std::vector<AtlasPage> pages; // one but for a multipack
    std::string image_path;  // pages[0].image_path
    int width = 0, height = 0; // pages[0]'s stated size
    std::vector<AtlasFrame> frames; // in file order (page by page)
    // meta.scale as PixiJS reads it (a number or a numeric string; 1 when
    // absent, 0 when unreadable). We place frames at their texel size, as
    // Phaser does; a scene that uses a sheet with scale != 1 is warned.
    double scale = 1;
    // What the reader assumed to read the file as engines do (a trimmed
    // sprite reaching past its sourceSize): one line each naming the file
    // and the frame (report_warnings prints them, or refuses with --strict).
    std::vector<std::string> warnings;
    // Frame index by name (read_atlas fills it); find() searches
    // linearly when it does not describe `frames`.
    std::unordered_map<std::string, std::size_t> by_name;
    const AtlasFrame* find(const std::string& name) const;
    // The JSON's bytes as read_atlas read them (null for a plist):
    // atlas_polygons_json writes from these, never from the file again, so
    // a file replaced meanwhile cannot pair its frames with these.
    std::shared_ptr<const std::string> text;
};

// Any of the forms above, told by content (a plist starts with '<').
// Frames whose spriteSourceSize w/h differ from the frame's (Aseprite, some
// Flash exporters) are read as Phaser and PixiJS read them: the frame's
// size is the trimmed sprite's, spriteSourceSize x/y its offset.
// Frames are texels of the decoded page, as PixiJS and Phaser read them
// (neither reads meta.size): check_atlas_pages checks them against it.
Atlas read_atlas(const std::string& path);
// Against the pages' real sizes (`sizes[k]` = {width, height} of
// pages[k]'s image, from its header or its decode): an Error for a frame
// whose texels lie outside its page; a warning line in atlas.warnings for
// a page whose stated size (meta.size) differs.
void check_atlas_pages(Atlas& atlas, const std::vector<std::array<int, 2>>& sizes);

// Where an element showing `frame` samples the page and how it is placed:
// `sprite_transform` maps the untrimmed sprite's texel space (origin at
// its top-left) to the screen; the result's rect/transform are an
// Element's, accounting for trimming and rotation.
struct FramePlacement {
    Rect rect;
    std::array<double, 6> transform{1, 0, 0, 1, 0, 0};
};
FramePlacement place_frame(const AtlasFrame& frame, const std::array<double, 6>& sprite_transform);

// Polygon export: the atlas JSON at `path` written back with TexturePacker's
// polygon fields added to every frame, from the boundary polygons of each
// frame's analysis (frames[i] for atlas.frames[i]; the pipeline's
// pipeline::atlas_with_polygons computes them): "vertices" (untrimmed sprite
// coordinates, as TexturePacker writes them), "verticesUV" (page texels)
// and "triangles" (index triples into both, by ear clipping). Every other
// field is kept as read, in its order; fully transparent frames get empty
// lists. Engines that read TexturePacker polygons (cocos2d-x, PixiJS,
// Defold) then draw our tighter polygons. A multipack gets them in every
// page's frames. atlas_polygons_plist writes a cocos2d-x format 3 plist
// instead (what a plist input, or pipeline::AtlasPolygonOptions::plist,
// gets) with "triangles", "vertices" and "verticesUV" (space-separated
// integers, as SpriteFrameCache reads them), so cocos2d-x makes polygon
// sprites.
struct AtlasPolygonStats {
    int frames = 0;
    std::int64_t vertices = 0, triangles = 0;
    double frame_area = 0;   // summed frame rects (what quads would draw)
    double polygon_area = 0; // summed boundary polygon areas
    // plist output: frames whose polygons have vertices off the integer
    // grid that could not be rounded keeping every texel inside (written
    // as their frame rectangle instead).
    int rectangle_frames = 0;
};
std::string atlas_polygons_json(const std::string& path, const Atlas& atlas, const std::vector<ImageAnalysis>& frames,
                                AtlasPolygonStats* stats = nullptr);
// The same polygons as a cocos2d-x format 3 plist (one page: `page`, the
// atlas' only page; `filter` the one the frames were analyzed for, used
// to check rounded polygons still hold every texel).
std::string atlas_polygons_plist(const std::string& path, const Atlas& atlas, ImageView page, const std::vector<ImageAnalysis>& frames,
                                 Filter filter, AtlasPolygonStats* stats = nullptr);

// Godot: a text scene (.tscn, Godot 3's format 2) holding one Polygon2D
// that draws `frame` through `boundary` (its boundary polygons in page
// texels): "texture" the page at `texture_path` (res://..., or relative to
// the scene's directory), "polygon" the vertices in the untrimmed sprite's
// coordinates (origin its top-left), "uv" the same points in page texels,
// "polygons" one index triple per triangle of our ear clipping. A fully
// transparent frame gets empty arrays (it draws nothing).
std::string godot_polygon_scene(const AtlasFrame& frame, const std::vector<Polygon>& boundary, const std::string& texture_path);

// ---- Meshes files (docs/mesh-format.md): what `depthcull optimize`
// writes and a game loads, in two forms (JSON and a compact little-endian
// binary) holding the same content.

// A run of a draw's vertices that shows an animated element
// (depthcull::AnimatedRun, scene.h), as the files' "animated" lists them.
using AnimatedRun = depthcull::AnimatedRun;

// Everything a meshes file holds, in either form: what meshes_document
// makes from a scene and what the readers give back. Writing a document
// that was read gives the bytes that were read (the same form and output
// path), and either form's document writes as the other form's bytes.
struct MeshesDocument {
    // id, path, width, height, colour key or fill. A reader resolves paths
    // against the file's directory (as read_scene resolves a scene's);
    // the writers write them relative to the output's.
    std::vector<SceneImage> images;
    // Draw::image indexes `images`. The files carry no element spans (a
    // reader leaves Draw::element_spans empty); depth_denominator comes
    // from stats.depth_bits. Viewport, depth test, filter, stats and the
    // insertion points are the meshes'.
    SceneMeshes meshes;
    // The scene's animations (frame images index `images`) and the vertex
    // runs that show them, in draw order; both empty for unanimated scenes.
    std::vector<Animation> animations;
    std::vector<AnimatedRun> animated;
    // stats.seconds: the reconstruction's wall time, set by the caller that
    // measured it (`depthcull optimize` without --no-timing); a reader
    // gives the file's. 0, the default, says "not measured" and keeps
    // outputs the same bytes on every run: no writer reads a clock.
    double seconds = 0;
};

// The document of `scene` reconstructed as `meshes` (moved in: the draws
// are not copied when the caller passes an rvalue): the scene's images and
// animations, and the animated runs, from the element spans of meshes made
// with ReconstructOptions::element_spans (adjacent spans of one element are
// one run). An Error when the scene is animated and a non-empty draw has no
// element spans. seconds is 0.
MeshesDocument meshes_document(const Scene& scene, SceneMeshes meshes);

// The JSON form: viewport, images (paths relative to the directory of
// `output_path`: the cwd when it is empty or "-"), draws in drawing order,
// stats, then the animations and insertion points when there are some.
// Per form, one writer of each kind: the bytes whole; the same bytes
// handed to `write` in pieces of about a MiB as they are made (a large
// meshes file never sits in memory whole); a file written atomically
// (write_file_atomic), streamed into its temporary.
std::string meshes_to_json(const MeshesDocument& document, const std::string& output_path);
void stream_meshes_json(const WriteBytes& write, const MeshesDocument& document, const std::string& output_path);
void write_meshes_json(const std::string& path, const MeshesDocument& document);
// The binary form, the same content.
std::string meshes_to_binary(const MeshesDocument& document, const std::string& output_path);
void stream_meshes_binary(const WriteBytes& write, const MeshesDocument& document, const std::string& output_path);
void write_meshes_binary(const std::string& path, const MeshesDocument& document);

// Limits of the mesh readers, checked before anything is allocated for
// them: a hostile file cannot make a reader allocate more than it holds.
inline constexpr std::size_t kMaxMeshImages = std::size_t(1) << 16;
inline constexpr std::size_t kMaxMeshDraws = std::size_t(1) << 24;
inline constexpr std::size_t kMaxMeshVertices = std::size_t(1) << 25;     // all draws together (1.2 GB of vertices)
inline constexpr std::size_t kMaxMeshIndices = std::size_t(3) << 25;      // all draws together
inline constexpr std::size_t kMaxMeshStringBytes = std::size_t(1) << 16;  // an image id or path
inline constexpr std::size_t kMaxMeshAnimations = std::size_t(1) << 20;
inline constexpr std::size_t kMaxMeshAnimationFrames = std::size_t(1) << 16; // per animation
inline constexpr std::size_t kMaxMeshInsertionPoints = std::size_t(1) << 16;

// A meshes file in either form, told apart by the binary magic "DCMESH".
// Bad files throw an Error naming the file and the place: a byte offset
// (binary) or a JSON path ("draws[3].indices[7]"). Checked: the formats'
// shapes and known enums, the limits above, every float finite, z in
// [0, 1], indices below their draw's vertex count and a multiple of 3,
// draws naming existing images.
MeshesDocument read_meshes(const std::string& path);
// From memory, one reader per form: `name` names the source in errors; relative
// image paths are resolved against `base_dir` (kept as written when it is
// empty), so meshes_to_json(meshes_from_json(text, name), "") == text.
MeshesDocument meshes_from_json(std::string_view text, const std::string& name, const std::string& base_dir = "");
MeshesDocument meshes_from_binary(std::string_view bytes, const std::string& name, const std::string& base_dir = "");
// True when `bytes` starts with the binary form's magic.
bool is_binary_meshes(std::string_view bytes);

} // namespace depthcull::io
