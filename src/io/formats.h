// Internal: the scene readers that io::read_scene dispatches to, and what
// every reader shares to keep its errors ours.
#pragma once

#include <filesystem>
#include <new>
#include <stdexcept>
#include <string>
#include <string_view>

#include "depthcull/io.h"

namespace depthcull::io {

// The readers over a file's bytes: `path` names it in errors, picks the
// format (as read_scene does) and resolves the relative paths it names.
Scene scene_json_from_text(std::string_view text, const std::string& path, const LoadOptions& options); // scene_json.cpp
Scene tiled_map_from_bytes(std::string_view bytes, const std::string& path, const LoadOptions& options); // tiled_map.cpp, gzipped or not
// read_scene over bytes already read (the fuzz harnesses): the same
// checks, and Error the only exception.
Scene scene_from_bytes(std::string_view bytes, const std::string& path, const LoadOptions& options = {}); // read_scene.cpp
// read_atlas over the JSON's text.
Atlas texturepacker_from_text(std::string_view text, const std::string& path); // texturepacker.cpp

// Width and height from the PNG signature and IHDR chunk, without decoding;
// Error when the file is missing, not a PNG, or over our size limits.
// With `files`, the file is read whole and kept there for the decode that
// follows (while they keep files); otherwise only its first 24 bytes.
void png_size(const std::string& path, int* width, int* height, ImageFiles* files = nullptr); // png.cpp
// The same from a PNG's first bytes (24 suffice); `name` names it in errors.
void png_size_from_bytes(std::string_view bytes, const std::string& name, int* width, int* height); // png.cpp
// Up to `size` bytes from the start of a regular file, in one read;
// Error "cannot open image <path> (...)" when it is missing or cannot
// be opened, and check_input_file's errors (directories, FIFOs, devices,
// files over kMaxFileBytes) before anything is opened.
std::string read_image_head(const std::string& path, std::size_t size); // file.cpp
// A directory of PNGs (recursive) or one PNG as a scene: each image once,
// in rows without overlap (sprite_folder.cpp).
bool is_sprite_source(const std::string& path);
Scene read_sprite_folder(const std::string& path, const LoadOptions& options);
// image_size (io.h): the same for any image read_image reads.

// Error "<where>: ..." unless the viewport is finite, within
// limits::kMaxCoordinate and 1..kMaxImageSide per side (read_scene.cpp).
void check_viewport(const Viewport& viewport, const std::string& where);

bool ends_with(const std::string& s, const std::string& suffix);

// cocos2d-x sprite frames (.plist, formats 2 and 3) as an Atlas (cocos2d_plist.cpp).
Atlas load_cocos2d_plist(const std::string& path);

// Error unless `path` is a regular file within kMaxFileBytes.
void check_input_file(const std::string& path); // file.cpp

// check_json_document and throw_json_error (the checks every JSON reader
// makes, pipeline's profile reader too): io.h.
inline void check_json_depth(std::string_view text, const std::string& path) { check_json_document(text, path); }
// The same for an XML document as pugixml parses it: about 64 bytes a
// node, so 250 MiB of "<a/>" would be a DOM of several GiB. Every XML
// reader calls it before parsing.
void check_xml_document(std::string_view text, const std::string& path);
// The estimates themselves (the whole text, so errors say how far over); the
// JSON one also checks nesting. A reader that keeps several documents at
// once (a Tiled map and its templates) sums them and checks the sum.
std::uint64_t json_document_bytes(std::string_view text, const std::string& path);
std::uint64_t xml_document_bytes(std::string_view text);
void check_documents_held(std::uint64_t bytes, const std::string& path);


// Colour keys (SceneImage::trans) as files write them: "RRGGBB" or
// "#RRGGBB" in, "rrggbb" out.
std::uint32_t parse_color_key(const std::string& text, const std::string& where);
// color_key_text: io.h.

// Whether `text` is UTF-8 (JSON's encoding); check_utf8 throws Error
// "<where>: '<text>' is not valid UTF-8 ..." when it is not. Paths and
// names come from file systems and XML, which allow other bytes.
void check_utf8(const std::string& text, const std::string& where);
// How errors name an output: its path, "stdout" for "" and "-".
inline std::string output_name(const std::string& path) { return path.empty() || path == "-" ? "stdout" : path; }

} // namespace depthcull::io
