// depthcull: the limits on what we read, in one place (README, "Limits").
// A hostile or broken file must not make us recurse, allocate or loop
// without bound, so every reader checks its input against these before it
// allocates, and names the limit in its error ("... more than 256 nested
// groups (kMaxNestingDepth)"). Each is far above what a real game asset
// needs; the image limits live in image.h beside Image.
#pragma once

#include <cstdint>
#include <cstddef>

#include "depthcull/image.h" // kMaxImageSide, kMaxImageTexels

namespace depthcull::limits {

// Files: larger inputs are refused before they are read; inputs must be
// regular files (not /dev/zero, FIFOs or directories).
inline constexpr std::uint64_t kMaxFileBytes = std::uint64_t(1) << 30;  // 1 GiB, any input file
inline constexpr std::size_t kMaxXmlBytes = std::size_t(256) << 20;     // a Tiled map / tileset / template after gunzip
// Parsed documents (every JSON and XML input): the memory their parse
// would take, estimated in one pass over the text before parsing. Bytes
// alone do not bound it: 250 MiB of XML can be a DOM of 7 GiB.
inline constexpr std::uint64_t kMaxDocumentBytes = std::uint64_t(1) << 30; // 1 GiB
// Image files a scene load keeps read for their decode (io::ImageFiles),
// all together; past it, a file is read for its size and again to decode.
inline constexpr std::uint64_t kMaxKeptImageBytes = std::uint64_t(256) << 20;
// Decoded images (RGBA8) a scene may hold together, one per (file, colour
// key) its elements show, summed from the headers before any decode: a
// 55 KB PNG can say 16384^2 (1 GiB). The analysis' own scratch memory is
// bounded apart (kMaxAnalysisBytes, analyze.h).
inline constexpr std::uint64_t kMaxDecodedBytes = std::uint64_t(2) << 30;

// Nesting of input structures (Tiled <group> layers, JSON arrays and
// objects): deeper input is refused rather than walked recursively.
inline constexpr int kMaxNestingDepth = 256;

// Coordinates and numbers read from files and options: finite and within
// +-kMaxCoordinate world units (keeps every product finite and exact
// enough; far beyond any screen).
inline constexpr double kMaxCoordinate = 1e9;

// Frames drawn (render, bench, report): a viewport of at most this many
// pixels (8192 x 8192). Each frame is held several times over (colour,
// depth, read back, compared), so a 16384^2 viewport would need GiBs.
inline constexpr std::int64_t kMaxFramePixels = std::int64_t(1) << 26;

// Scenes.
inline constexpr std::size_t kMaxSceneImages = std::size_t(1) << 16;
inline constexpr std::int64_t kMaxSceneElements = std::int64_t(1) << 24; // scene JSON
inline constexpr std::size_t kMaxAtlasFrames = 1'000'000;                // one TexturePacker page

// The element graph (paper 2.3, docs/element-graph.md): candidate pairs
// its broad phase compares. Past the budget, the most crowded grid cells
// keep painter's order among their elements (a chain) instead of comparing
// all pairs, so edges <= kGraphPairBudget + 2 * elements. Not an error:
// the result stays correct, only less reordered.
inline constexpr std::uint64_t kGraphPairBudget = std::uint64_t(1) << 22;

// --target (pipeline::plan_target): the elements its cost model weighs.
// Each plan's choice reconstructs and rasterizes dozens of contestant frames
// of the whole scene (about 1.5 KiB per element each, and minutes past a few
// hundred thousand elements); past this a scene is planned without a target,
// with a warning (an error with --strict). --viewport with --cull plans one
// camera's elements.
inline constexpr std::size_t kMaxTargetElements = std::size_t(1) << 18;

// Worker threads (-j, PrepareOptions::threads): more are clamped to this.
// Each costs a stack and a task slot; past a few hundred they only add
// contention.
inline constexpr unsigned kMaxThreads = 256;

// Tiled maps.
inline constexpr int kMaxMapSide = 1 << 20;                          // cells per side; chunk coordinates within +-this
inline constexpr std::int64_t kMaxLayerCells = std::int64_t(1) << 24; // one tile layer (its chunks summed)
inline constexpr std::int64_t kMaxMapCells = std::int64_t(1) << 26;   // all tile layers of a map together
inline constexpr std::int64_t kMaxMapElements = 4'000'000;            // elements a map may produce
inline constexpr int kMaxLayers = 10'000;                             // layers per map or group
inline constexpr int kMaxTilesets = 10'000;
// Animations (Scene::animations): the frames are combined texel by texel
// before one analysis, so frames and frames x frame texels are bounded
// (400 frames of 4096^2 would take 11 s from a 24 KB map).
inline constexpr std::size_t kMaxAnimationFrames = 65'536;                // per animation
inline constexpr std::uint64_t kMaxAnimationTexels = std::uint64_t(1) << 30; // frames x frame texels, per animation

} // namespace depthcull::limits
