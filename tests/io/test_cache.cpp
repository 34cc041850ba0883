// The analysis cache: keys, round trips, corrupt entries recomputed, and
// a re-run of a scene served from the cache with identical results.
#include <cstring>
#include <thread>

#include <gtest/gtest.h>

#include "pipeline/cache.h"
#include "test_scene_json_helpers.h"

namespace depthcull::test {
namespace {

using namespace depthcull::io;
using namespace depthcull::pipeline;

ImageAnalysis sample_analysis() {
    Image img = ascii_image({"........", "..####..", ".######.", ".######.", ".######.", "..####..", "........", "........"});
    return analyze_image(img.view(), img.view().bounds(), {});
}

TEST(Cache, KeyDependsOnTexelsSizeAndOptionsNotPosition) {
    Image img = ascii_image({"##..##..", "##..##..", "+.......", "........"});
    AnalyzeOptions o;
    CacheKey a = analysis_key(img.view(), {0, 0, 2, 2}, o);
    EXPECT_EQ(a.hex().size(), 32u);
    // Same alphas elsewhere (ascii_image colours vary with position): the
    // analysis sees only alpha, so the key does too.
    EXPECT_EQ(a.hex(), analysis_key(img.view(), {4, 0, 2, 2}, o).hex());
    EXPECT_NE(a.hex(), analysis_key(img.view(), {0, 1, 2, 2}, o).hex()); // different texels
    EXPECT_NE(a.hex(), analysis_key(img.view(), {0, 0, 2, 1}, o).hex()); // different size
    AnalyzeOptions linear = o;
    linear.filter = Filter::linear;
    EXPECT_NE(a.hex(), analysis_key(img.view(), {0, 0, 2, 2}, linear).hex());
    AnalyzeOptions fewer = o;
    fewer.boundary.max_vertices = 8;
    EXPECT_NE(a.hex(), analysis_key(img.view(), {0, 0, 2, 2}, fewer).hex());
    EXPECT_NE(hash_bytes_128("a", 1).hex(), hash_bytes_128("b", 1).hex());
}

TEST(Cache, RoundTripMovesPolygonsWithTheRect) {
    ImageAnalysis a = sample_analysis();
    CacheKey key = hash_bytes_128("k", 1);
    std::string bytes = serialize_analysis(key, a);
    auto back = parse_analysis(bytes, key, a.rect);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->boundary, a.boundary);
    EXPECT_EQ(back->opaque, a.opaque);
    EXPECT_EQ(back->stats.nontransparent_texels, a.stats.nontransparent_texels);
    // The same texels at another place in another image.
    Rect moved{a.rect.x + 16, a.rect.y + 4, a.rect.w, a.rect.h};
    auto shifted = parse_analysis(bytes, key, moved);
    ASSERT_TRUE(shifted);
    EXPECT_EQ(shifted->boundary[0][0].x, a.boundary[0][0].x + 16);
    EXPECT_EQ(shifted->rect, moved);
}

TEST(Cache, EveryCorruptionIsRejected) {
    ImageAnalysis a = sample_analysis();
    CacheKey key = hash_bytes_128("k", 1);
    const std::string good = serialize_analysis(key, a);
    for (std::size_t i = 0; i < good.size(); ++i) {
        std::string bad = good;
        bad[i] = char(bad[i] ^ 0x5a);
        EXPECT_FALSE(parse_analysis(bad, key, a.rect)) << "flipped byte " << i;
    }
    for (std::size_t n = 0; n < good.size(); n += 7) EXPECT_FALSE(parse_analysis(good.substr(0, n), key, a.rect)) << n;
    EXPECT_FALSE(parse_analysis(good + "x", key, a.rect));
    EXPECT_FALSE(parse_analysis(good, hash_bytes_128("other", 5), a.rect)); // another key's entry
}

// An entry copied from another image with its 16 key bytes rewritten
// (issue 21): the checksum covered only the payload, so it was trusted and
// put one image's polygons on another.
TEST(Cache, EntryWithItsKeyRewrittenIsRejected) {
    EXPECT_GE(kCacheFormatVersion, 3u); // the checksum covers the header since 3
    ImageAnalysis a = sample_analysis();
    const CacheKey theirs = hash_bytes_128("another image", 13), ours = hash_bytes_128("this image", 10);
    std::string copied = serialize_analysis(theirs, a);
    ASSERT_TRUE(parse_analysis(copied, theirs, a.rect));
    std::memcpy(copied.data() + 8, ours.words.data(), 16); // after "DCAN" and the version
    EXPECT_FALSE(parse_analysis(copied, ours, a.rect));
    EXPECT_TRUE(parse_analysis(serialize_analysis(ours, a), ours, a.rect));
}

TEST(Cache, SceneRerunIsServedFromTheCacheAndCorruptEntriesAreRecomputed) {
    SceneDir dir("cache");
    dir.standard_art();
    std::string scene = dir.write("scene.json", R"({"images": [{"id": "blob", "path": "art/blob.png"}, {"id": "tiles", "path": "art/tiles.png"}],
        "elements": [{"image": "blob"}, {"image": "tiles", "rect": [0, 0, 8, 8]}, {"image": "tiles", "rect": [8, 0, 8, 8]},
                     {"image": "blob", "transform": [1, 0, 0, 1, 4, 4]}]})");
    pipeline::PrepareOptions o;
    o.cache_dir = dir.path("cache");
    o.threads = 2;
    pipeline::PreparedScene first = pipeline::prepare_scene(scene, o);
    EXPECT_EQ(first.analyzed, 3);
    EXPECT_EQ(first.cache_hits, 0);
    pipeline::PreparedScene second = pipeline::prepare_scene(scene, o);
    EXPECT_EQ(second.analyzed, 0);
    EXPECT_EQ(second.cache_hits, 3);
    for (std::size_t i = 0; i < first.analysis.images.size(); ++i) {
        EXPECT_EQ(second.analysis.images[i].boundary, first.analysis.images[i].boundary);
        EXPECT_EQ(second.analysis.images[i].opaque, first.analysis.images[i].opaque);
        EXPECT_EQ(second.analysis.images[i].rect, first.analysis.images[i].rect);
    }
    // Truncate every entry (as a crash mid-write without rename could not,
    // but a disk error might): all are recomputed, none trusted.
    for (auto& f : std::filesystem::recursive_directory_iterator(dir.path("cache")))
        if (f.is_regular_file()) std::filesystem::resize_file(f.path(), 10);
    pipeline::PreparedScene third = pipeline::prepare_scene(scene, o);
    EXPECT_EQ(third.analyzed, 3);
    EXPECT_EQ(third.analysis.images[0].boundary, first.analysis.images[0].boundary);
    EXPECT_EQ(pipeline::prepare_scene(scene, o).cache_hits, 3); // rewritten
}

// Concurrent runs on one cache directory (as parallel asset builds do):
// entries are written by rename, so every run sees either no entry or a
// whole one, and all runs agree. Leftover temporary files of a killed
// writer are never read.
TEST(Cache, ConcurrentRunsAgreeAndStrayFilesAreIgnored) {
    SceneDir dir("cache_concurrent");
    dir.standard_art();
    std::string scene = dir.write("scene.json", R"({"images": [{"id": "blob", "path": "art/blob.png"}, {"id": "tiles", "path": "art/tiles.png"}],
        "elements": [{"image": "blob"}, {"image": "tiles", "rect": [0, 0, 8, 8]}, {"image": "tiles", "rect": [8, 0, 8, 8]},
                     {"image": "tiles", "rect": [4, 0, 8, 8]}, {"image": "tiles", "rect": [2, 2, 6, 6]}]})");
    pipeline::PrepareOptions o;
    o.cache_dir = dir.path("cache");
    o.threads = 1;
    pipeline::PreparedScene reference = pipeline::prepare_scene(scene, pipeline::PrepareOptions{});
    // A killed writer's temporary file beside where an entry will go.
    CacheKey first_key = analysis_key(reference.view(0), reference.analysis.images[0].rect, o.analyze);
    std::string entry = cache_entry_path(o.cache_dir, first_key);
    std::filesystem::create_directories(std::filesystem::path(entry).parent_path());
    dir.write(std::filesystem::relative(std::filesystem::path(entry).parent_path() / ".stray.tmp123.4", dir.root).string(), "garbage");
    std::vector<pipeline::PreparedScene> runs(8);
    std::vector<std::thread> threads;
    for (std::size_t t = 0; t < runs.size(); ++t) threads.emplace_back([&, t] { runs[t] = pipeline::prepare_scene(scene, o); });
    for (auto& t : threads) t.join();
    for (const pipeline::PreparedScene& run : runs) {
        ASSERT_EQ(run.analysis.images.size(), reference.analysis.images.size());
        EXPECT_EQ(run.analyzed + run.cache_hits, int(reference.analysis.images.size()));
        for (std::size_t i = 0; i < run.analysis.images.size(); ++i) {
            EXPECT_EQ(run.analysis.images[i].boundary, reference.analysis.images[i].boundary);
            EXPECT_EQ(run.analysis.images[i].opaque, reference.analysis.images[i].opaque);
        }
    }
    EXPECT_EQ(pipeline::prepare_scene(scene, o).cache_hits, int(reference.analysis.images.size()));
}

} // namespace
} // namespace depthcull::test
