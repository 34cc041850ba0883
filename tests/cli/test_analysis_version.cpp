// Guards kAnalysisVersion: the analysis cache trusts entries with the same
// key, and the key includes kAnalysisVersion, so any change to what the
// analysis outputs must bump it. This golden digest of the analysis of the
// bundled example art fails first; then bump kAnalysisVersion in
// include/depthcull/analyze.h and update both constants below.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "depthcull/analyze.h"
#include "depthcull/io.h"

using namespace depthcull;

namespace {

constexpr int kGoldenVersion = 4;
constexpr std::uint64_t kGoldenDigest = 9519946284819868573ull;

std::uint64_t fnv(std::uint64_t h, const void* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 0x100000001b3ull;
    return h;
}

std::uint64_t digest_polygons(std::uint64_t h, const std::vector<Polygon>& polys) {
    for (const Polygon& p : polys) {
        std::size_t n = p.size();
        h = fnv(h, &n, sizeof n);
        for (const Vec2& v : p) h = fnv(fnv(h, &v.x, sizeof v.x), &v.y, sizeof v.y);
    }
    return h;
}

} // namespace

TEST(AnalysisVersion, GoldenDigestOfTheExampleArt) {
    std::vector<std::string> files;
    for (auto& e : std::filesystem::directory_iterator(std::string(DEPTHCULL_SOURCE_DIR) + "/examples/art")) files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const auto& f : files) {
        Image img = io::read_png(f);
        for (Filter filter : {Filter::nearest, Filter::linear})
            for (OpaqueMethod method : {OpaqueMethod::fast, OpaqueMethod::paper, OpaqueMethod::grow}) {
                AnalyzeOptions o;
                o.filter = filter;
                o.opaque.method = method;
                ImageAnalysis a = analyze_image(img.view(), img.view().bounds(), o);
                h = digest_polygons(digest_polygons(h, a.boundary), a.opaque);
            }
    }
    EXPECT_EQ(kAnalysisVersion, kGoldenVersion) << "update kGoldenVersion and kGoldenDigest together";
    EXPECT_EQ(h, kGoldenDigest) << "the analysis output changed: bump kAnalysisVersion in include/depthcull/analyze.h, "
                                   "then set kGoldenVersion = kAnalysisVersion and kGoldenDigest = "
                                << h;
}
