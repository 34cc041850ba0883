// A scratch directory with small PNGs and scene files, for the scene,
// cache and mesh-output tests. Unique per process so test programs can
// run side by side.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "testing/ascii_image.h"

namespace depthcull::test {

struct SceneDir {
    std::filesystem::path root;

    explicit SceneDir(const std::string& name) {
        root = std::filesystem::temp_directory_path() / ("dc_" + name + "_" + std::to_string(::getpid()));
        std::filesystem::remove_all(root);
        std::filesystem::create_directories(root / "art");
    }
    ~SceneDir() {
        std::error_code ec;
        std::filesystem::remove_all(root, ec);
    }
    std::string path(const std::string& rel) const { return (root / rel).string(); }
    void png(const std::string& rel, const std::vector<std::string>& rows) const { io::write_png(path(rel), ascii_image(rows).view()); }
    std::string write(const std::string& rel, const std::string& text) const {
        std::ofstream(path(rel)) << text;
        return path(rel);
    }
    // A blob with a transparent rim and an opaque core, and a 2x1 atlas of
    // two 8x8 tiles.
    void standard_art() const {
        png("art/blob.png", {"........", "..####..", ".######.", ".######.", ".######.", ".######.", "..####..", "........"});
        png("art/tiles.png", {"########++++++++", "########++++++++", "########++++++++", "########++++++++",
                              "########++++++++", "########++++++++", "########++++++++", "########++++++++"});
    }
};

} // namespace depthcull::test
