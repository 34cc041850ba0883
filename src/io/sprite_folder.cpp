// A folder of sprites (or one sprite) as a scene: every PNG once, laid out
// in rows like a contact sheet, so each command that takes a scene
// (optimize, render, bench, report) also takes the art of a game before
// any level exists. The layout is deterministic (files in byte order of
// their paths) and no sprite overlaps another, so the frame shows each
// sprite as it is and the report's per-image table lists them all.
#include <algorithm>
#include <filesystem>

#include "depthcull/limits.h"
#include "io/formats.h"

namespace fs = std::filesystem;

namespace depthcull::io {

namespace {

constexpr int kGap = 4;            // pixels between sprites
constexpr int kRowWidth = 1024;    // a row wraps past this (wider sprites get a row of their own)

bool is_png(const fs::path& p) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".png";
}

std::vector<std::string> sprite_files(const std::string& path) {
    std::error_code ec;
    if (!fs::is_directory(path, ec)) return {path};
    std::vector<std::string> found;
    for (auto it = fs::recursive_directory_iterator(path, fs::directory_options::skip_permission_denied, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (is_png(it->path()) && it->is_regular_file(ec)) found.push_back(it->path().string());
        if (found.size() > limits::kMaxSceneImages)
            throw Error(path + ": more than " + std::to_string(limits::kMaxSceneImages) + " PNG images (kMaxSceneImages)");
    }
    if (ec) throw Error(path + ": cannot list the directory (" + ec.message() + ")");
    if (found.empty()) throw Error(path + ": no PNG images in the directory");
    std::sort(found.begin(), found.end());
    return found;
}

} // namespace

bool is_sprite_source(const std::string& path) {
    std::error_code ec;
    return fs::is_directory(path, ec) || is_png(fs::path(path));
}

Scene read_sprite_folder(const std::string& path, const LoadOptions& options) {
    Scene scene;
    int x = 0, y = 0, row_height = 0, width = 0;
    for (const std::string& file : sprite_files(path)) {
        SceneImage image;
        image.path = file;
        png_size(file, &image.width, &image.height, options.image_files);
        // Ids: the path below the folder, unique because paths are.
        std::error_code ec;
        fs::path rel = fs::path(file).lexically_relative(path);
        image.id = fs::is_directory(path, ec) && !rel.empty() ? rel.generic_string() : fs::path(file).filename().string();
        if (x > 0 && x + image.width > kRowWidth) {
            x = 0;
            y += row_height + kGap;
            row_height = 0;
        }
        if (y > limits::kMaxCoordinate - kMaxImageSide)
            throw Error(path + ": the sprites laid out in rows reach beyond +-1e9 (kMaxCoordinate)");
        Element e;
        e.image = int(scene.images.size());
        e.rect = {0, 0, image.width, image.height};
        e.transform = {1, 0, 0, 1, double(x), double(y)};
        scene.elements.push_back(e);
        width = std::max(width, x + image.width);
        row_height = std::max(row_height, image.height);
        x += image.width + kGap;
        scene.images.push_back(std::move(image));
    }
    const int height = y + row_height;
    if (options.has_viewport) {
        scene.viewport = options.viewport;
    } else {
        if (width > kMaxImageSide || height > kMaxImageSide)
            throw Error(path + ": the sprites laid out in rows need " + std::to_string(width) + "x" + std::to_string(height) +
                        " px, more than " + std::to_string(kMaxImageSide) + " (kMaxImageSide): give --viewport");
        scene.viewport = {0, 0, std::max(width, 1), std::max(height, 1)};
    }
    return scene;
}

} // namespace depthcull::io
