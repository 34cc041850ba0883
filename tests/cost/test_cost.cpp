// The cost model (issue 14): the Table 2 fit, profiles, features and the
// --target choice's determinism and guarantees.
#include <cmath>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "depthcull/cost.h"
#include "depthcull/overdraw.h"
#include "depthcull/target.h"
#include "testing/corpus.h"

namespace depthcull {
namespace {

std::string data(const std::string& name) { return std::string(DEPTHCULL_SOURCE_DIR) + "/tests/data/" + name; }

TEST(Table2Fit, ReproducesThePapersFit) {
    const std::vector<Table2Row> rows = pipeline::read_table2_tsv(data("paper-table2.tsv"));
    ASSERT_EQ(rows.size(), 57u); // 19 scenes x 3 modes
    Table2Fit fit;
    ASSERT_TRUE(fit_table2(rows, &fit));
    EXPECT_NEAR(fit.ms, 12.75, 0.01);
    EXPECT_NEAR(fit.ms_per_draw * 1000, 1.7, 0.01);      // us per draw call
    EXPECT_NEAR(fit.ms_per_triangle * 1000, 0.08, 0.001); // us per triangle
    EXPECT_NEAR(fit.ms_per_overdraw, 3.51, 0.01);
    EXPECT_NEAR(fit.r2, 0.857, 0.002);
    // The built-in ipad1 profile is this fit.
    CostProfile ipad;
    ASSERT_TRUE(builtin_profile("ipad1", &ipad));
    EXPECT_NEAR(ipad.frame_us, fit.profile.frame_us, 1e-6);
    EXPECT_NEAR(ipad.draw_call_us, fit.profile.draw_call_us, 1e-9);
    EXPECT_NEAR(ipad.triangle_us, fit.profile.triangle_us, 1e-9);
    EXPECT_NEAR(ipad.fragment_blend_ns, fit.profile.fragment_blend_ns, 1e-9);
    // Predicting a Table 2 row through the features gives the fit's value.
    FrameFeatures f;
    f.pixels = 1024 * 768;
    f.draw_calls = 47;
    f.triangles = 25404;
    f.blend_fragments = std::int64_t(3.9 * 1024 * 768);
    EXPECT_NEAR(predict_ms(ipad, f), fit.ms + 47 * fit.ms_per_draw + 25404 * fit.ms_per_triangle + 3.9 * fit.ms_per_overdraw, 1e-3);
}

TEST(Profiles, BuiltinsAreCompleteAndRoundTrip) {
    for (const std::string& name : builtin_profile_names()) {
        CostProfile p;
        ASSERT_TRUE(builtin_profile(name, &p)) << name;
        std::string what;
        EXPECT_TRUE(profile_is_complete(p, &what)) << name << ": " << what;
        const CostProfile back = pipeline::profile_from_json(pipeline::profile_to_json(p), name);
        EXPECT_EQ(pipeline::profile_to_json(back), pipeline::profile_to_json(p));
        EXPECT_GE(min_opaque_area(p), 1);
    }
    CostProfile p;
    EXPECT_FALSE(builtin_profile("nope", &p));
}

TEST(Profiles, BadFilesGetOneLineErrors) {
    auto error_of = [](const std::string& text) {
        try {
            pipeline::profile_from_json(text, "p.json");
        } catch (const depthcull::Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CostProfile llvm;
    ASSERT_TRUE(builtin_profile("llvmpipe", &llvm));
    const std::string good = pipeline::profile_to_json(llvm);
    EXPECT_EQ(error_of(good), "");
    EXPECT_NE(error_of("{"), "");
    EXPECT_EQ(error_of("[]"), "p.json: a profile is a JSON object");
    std::string missing = good;
    missing.replace(missing.find("\"triangle_us\""), 13, "\"triangle_xx\"");
    EXPECT_NE(error_of(missing).find("\"triangle_us\" missing"), std::string::npos);
    std::string negative = good;
    negative.insert(negative.find("\"draw_call_us\": ") + 16, "-");
    EXPECT_NE(error_of(negative).find("draw_call_us"), std::string::npos);
    for (const std::string& e : {error_of("{"), error_of(missing), error_of(negative)}) EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_THROW(pipeline::resolve_target("nosuchprofile"), depthcull::Error);
}

TEST(Features, CountsPassesAndRejection) {
    SceneMeshes m;
    m.viewport = {0, 0, 10, 10};
    m.depth_test = true;
    auto quad = [](Draw& d, float x0, float y0, float x1, float y1, float z) {
        const auto b = std::uint32_t(d.vertex_count());
        for (auto [x, y] : {std::pair{x0, y0}, std::pair{x1, y0}, std::pair{x1, y1}, std::pair{x0, y1}})
            d.vertices.insert(d.vertices.end(), {x, y, z, 0, 0, 1, 1, 1, 1});
        d.indices.insert(d.indices.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
    };
    Draw o;
    o.pass = Pass::opaque;
    quad(o, 0, 0, 5, 10, 0.5f); // 50 pixels written
    Draw b;
    b.pass = Pass::blend;
    b.image = 1;
    quad(b, 0, 0, 10, 10, 0.25f); // 50 rejected behind it, 50 shaded
    m.draws = {o, b};
    const FrameFeatures f = frame_features(m);
    EXPECT_EQ(f.pixels, 100);
    EXPECT_EQ(f.draw_calls, 2);
    EXPECT_EQ(f.texture_switches, 2);
    EXPECT_EQ(f.triangles, 4);
    EXPECT_EQ(f.opaque_fragments, 50);
    EXPECT_EQ(f.blend_fragments, 50);
    EXPECT_EQ(f.rejected_fragments, 50);
    EXPECT_TRUE(f.depth_clear);
}

// One rasterizer (issue 22): the model counts the fragments the overdraw
// analyzer counts, GL's 1/256-pixel vertex snapping and fill rule
// included, on triangles placed off the pixel grid and overlapping at
// several depths (the model's own float scan, before, missed the sliver).
TEST(Features, FragmentsAreTheOverdrawAnalyzers) {
    SceneMeshes m;
    m.viewport = {0, 0, 40, 40};
    m.depth_test = true;
    std::mt19937 rng(22);
    std::uniform_int_distribution<int> coord(-3000, 43000); // thousandths of a pixel
    for (int k = 0; k < 120; ++k) {
        Draw d;
        d.pass = k % 3 == 0 ? Pass::opaque : Pass::blend;
        d.image = k % 2;
        const float z = float(k % 7) / 8.0f;
        for (int v = 0; v < 3; ++v)
            d.vertices.insert(d.vertices.end(), {float(coord(rng)) / 1000.0f, float(coord(rng)) / 1000.0f, z, 0, 0, 1, 1, 1, 1});
        d.indices = {0, 1, 2};
        m.draws.push_back(d);
    }
    {
        // A rect whose left edge GL snaps from x = 10.501 onto the pixel
        // centres at 10.5, which its fill rule then keeps: 16 fragments,
        // not the 12 a float scan of x >= 10.501 finds.
        Draw d;
        for (auto [x, y] : {std::pair{10.501f, 0.0f}, std::pair{14.0f, 0.0f}, std::pair{14.0f, 4.0f}, std::pair{10.501f, 4.0f}})
            d.vertices.insert(d.vertices.end(), {x, y, 0.9f, 0, 0, 1, 1, 1, 1});
        d.indices = {0, 1, 2, 0, 2, 3};
        m.draws.push_back(d);
    }
    const OverdrawStats s = analyze_overdraw(m, nullptr, true);
    const FrameFeatures f = frame_features(m, true);
    EXPECT_EQ(f.opaque_fragments + f.blend_fragments, s.shaded);
    EXPECT_EQ(f.opaque_fragments + f.blend_fragments + f.rejected_fragments, s.rasterized);
    EXPECT_EQ(f.opaque_blocks, s.blocks_opaque);
    EXPECT_EQ(f.blend_blocks, s.blocks_blend);
    EXPECT_GT(f.opaque_blocks, 0);
    EXPECT_GT(f.blend_blocks, 0);
    // Without a depth buffer (ReconstructOptions::depthless) nothing is
    // rejected and opaque-pass draws still write without blending.
    m.depth_test = false;
    const OverdrawStats t = analyze_overdraw(m);
    const FrameFeatures g = frame_features(m);
    EXPECT_EQ(g.rejected_fragments, 0);
    EXPECT_EQ(g.opaque_fragments, t.shaded_opaque);
    EXPECT_EQ(g.opaque_fragments + g.blend_fragments, t.shaded);
}

TEST(LeastSquares, ExactLine) {
    std::vector<std::vector<double>> x{{1, 0}, {1, 1}, {1, 2}};
    std::vector<double> b;
    double r2 = 0;
    ASSERT_TRUE(least_squares(x, {1, 3, 5}, &b, &r2));
    EXPECT_NEAR(b[0], 1, 1e-12);
    EXPECT_NEAR(b[1], 2, 1e-12);
    EXPECT_NEAR(r2, 1, 1e-12);
    EXPECT_FALSE(least_squares({{1, 1}, {1, 1}}, {1, 2}, &b));
}

} // namespace
} // namespace depthcull

// ---- Through the command line: calibration, determinism, pixel identity.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace depthcull {
namespace {

std::string cli() { return DEPTHCULL_CLI_PATH; }

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string temp(const std::string& name) { return ::testing::TempDir() + "depthcull_cost_" + name; }

TEST(Calibrate, QuickCalibrationWritesACompleteFiniteProfile) {
    if (cli().empty()) GTEST_SKIP() << "no CLI in this build";
    const std::string out = temp("profile.json");
    std::remove(out.c_str());
    const int rc = std::system((cli() + " calibrate --quick -q -o " + out + " 2>" + temp("cal.err")).c_str());
    if (rc != 0 && slurp(temp("cal.err")).find("no OpenGL") != std::string::npos) GTEST_SKIP() << "no GL here";
    ASSERT_EQ(rc, 0) << slurp(temp("cal.err"));
    const CostProfile p = pipeline::read_profile(out); // every term present, finite, >= 0
    std::string what;
    EXPECT_TRUE(profile_is_complete(p, &what)) << what;
    // Each term is a difference of two timings, so a busy machine can
    // measure one as free (CI once did, for triangles): the test asserts no
    // timing, only that such a profile never goes out unannounced.
    const std::string err = slurp(temp("cal.err"));
    if (p.name == "calibrated-software") {
        if (p.fragment_blend_ns <= 0) {
            EXPECT_NE(err.find("blended fragment"), std::string::npos) << err;
        }
        if (p.triangle_us + p.triangle_perimeter_ns_per_pixel <= 0) {
            EXPECT_NE(err.find("triangle"), std::string::npos) << err;
        }
        if (err.find("warning: calibrate:") != std::string::npos) {
            EXPECT_NE(err.find("without --quick"), std::string::npos) << err;
        }
    }
    // And it is usable as a target.
    const std::string meshes = temp("cal-meshes.json");
    EXPECT_EQ(std::system((cli() + " optimize " + DEPTHCULL_SOURCE_DIR + "/examples/meadow.json --no-cache -q --target " + out + " -o " + meshes).c_str()), 0);
}

// A TargetChoice is a value (issue 22): its analyses are held by index, so
// a copy works after the original is gone (before, the copy's pointers
// pointed into the original's storage: a use after free under ASan).
TEST(Target, ACopiedChoiceStandsAlone) {
    Scene scene;
    scene.viewport = {0, 0, 64, 64};
    scene.images = {{"back", "back.png", 32, 32}, {"front", "front.png", 16, 16}};
    const Polygon back_poly{{2, 2}, {30, 2}, {30, 30}, {2, 30}}, front_rect{{0, 0}, {16, 0}, {16, 16}, {0, 16}};
    std::vector<ImageAnalysis> analyses(2);
    analyses[0].rect = {0, 0, 32, 32};
    analyses[0].boundary = {back_poly};
    analyses[0].stats.nontransparent_texels = 28 * 28;
    analyses[1].rect = {0, 0, 16, 16};
    analyses[1].boundary = {front_rect};
    analyses[1].opaque = {front_rect};
    analyses[1].stats.nontransparent_texels = analyses[1].stats.opaque_texels = analyses[1].stats.opaque_covered_texels = 256;
    auto element = [](int image, int size, double x, double y) {
        Element e;
        e.image = image;
        e.rect = {0, 0, size, size};
        e.transform = {1, 0, 0, 1, x, y};
        return e;
    };
    scene.elements = {element(0, 32, 4, 4), element(1, 16, 10, 10), element(0, 32, 30, 30), element(1, 16, 40, 8)};
    std::vector<TargetCandidates> candidates(2);
    for (std::size_t k = 0; k < 2; ++k) candidates[k] = {{&analyses[k]}, {16}};
    CostProfile profile;
    ASSERT_TRUE(builtin_profile("llvmpipe", &profile));
    const std::vector<int> keys{0, 1, 0, 1};

    auto choice = std::make_unique<TargetChoice>(choose_for_target(scene, candidates, keys, profile, {}));
    SceneMeshes expected;
    ReconstructOptions options;
    options.opaque_polygons = choice->opaque_pass;
    ASSERT_EQ(reconstruct_scene(scene, choice->analysis, options, &expected), ReconstructStatus::ok);
    const TargetChoice copy = *choice;
    choice.reset(); // the original is gone

    ASSERT_EQ(copy.analysis.of_element.size(), scene.elements.size());
    for (std::size_t i = 0; i < scene.elements.size(); ++i) {
        const ImageAnalysis* a = copy.analysis.of(i);
        ASSERT_NE(a, nullptr) << i;
        EXPECT_TRUE(a >= copy.analysis.images.data() && a < copy.analysis.images.data() + copy.analysis.images.size()) << i;
    }
    SceneMeshes again;
    ASSERT_EQ(reconstruct_scene(scene, copy.analysis, options, &again), ReconstructStatus::ok);
    ASSERT_EQ(again.draws.size(), expected.draws.size());
    for (std::size_t d = 0; d < again.draws.size(); ++d) {
        EXPECT_EQ(again.draws[d].vertices, expected.draws[d].vertices);
        EXPECT_EQ(again.draws[d].indices, expected.draws[d].indices);
    }
}

// --target's candidates for an animated element are analyses of all its
// frames, as prepare_scene's analysis is: of frame 0 alone, the chosen
// meshes cut off the texels only later frames show (the look changed).
TEST(Target, AnimatedElementsCandidatesHoldEveryFrame) {
    pipeline::PreparedScene p;
    Image sheet;
    sheet.width = 16;
    sheet.height = 8;
    sheet.rgba.assign(16 * 8 * 4, 0);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            const int u = x % 8;
            // Frame 0 (x < 8): a 4x4 square; frame 1: a 6x4 one, higher.
            const bool on = x < 8 ? (u >= 2 && u < 6 && y >= 2 && y < 6) : (u >= 1 && u < 7 && y >= 1 && y < 5);
            if (on) sheet.rgba[std::size_t(y * 16 + x) * 4 + 3] = 255;
        }
    p.decoded.push_back(sheet);
    p.pixels = {0};
    SceneImage image;
    image.id = image.path = "anim.png";
    image.width = 16;
    image.height = 8;
    p.scene.images = {image};
    p.scene.viewport = {0, 0, 32, 32};
    Animation animation;
    animation.frames = {{0, {0, 0, 8, 8}, 100}, {0, {8, 0, 8, 8}, 100}};
    p.scene.animations = {animation};
    Element e;
    e.rect = {0, 0, 8, 8};
    e.animation = 0;
    e.transform = {1, 0, 0, 1, 4, 4};
    p.scene.elements = {e};
    const pipeline::PrepareOptions options;
    p.analysis.images = {pipeline::analyze_animation(p.views(), animation, options.analyze, "")};
    p.analysis.of_element = {0};
    const std::int64_t every_frame = p.analysis.images[0].stats.nontransparent_texels;
    ASSERT_EQ(every_frame, 16 + 24 - 12); // the union of the two squares
    for (const std::string& name : builtin_profile_names()) {
        CostProfile profile;
        ASSERT_TRUE(builtin_profile(name, &profile));
        const pipeline::TargetPlan plan = pipeline::plan_target(p, options, profile, {});
        ASSERT_FALSE(plan.candidates.empty());
        for (const ImageAnalysis& c : plan.candidates) EXPECT_EQ(c.stats.nontransparent_texels, every_frame) << name;
    }
}

TEST(Target, ChoicesAreDeterministicForAProfile) {
    if (cli().empty()) GTEST_SKIP() << "no CLI in this build";
    for (const char* target : {"llvmpipe", "ipad1"}) {
        std::string outputs[2];
        for (int k = 0; k < 2; ++k) {
            const std::string out = temp(std::string("det-") + target + std::to_string(k) + ".json");
            // -j 1, and -j 5: analyses and the four plans weighed on threads.
            const std::string cmd = cli() + " optimize " + DEPTHCULL_SOURCE_DIR + "/examples/meadow.json --no-cache -q --no-timing -j " +
                                    std::to_string(k == 0 ? 1 : 5) + " --target " + target + " -o " + out;
            ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
            outputs[k] = slurp(out);
        }
        EXPECT_FALSE(outputs[0].empty());
        EXPECT_EQ(outputs[0], outputs[1]) << target;
    }
}

TEST(Target, PixelIdentityHoldsForEveryTarget) {
    if (cli().empty()) GTEST_SKIP() << "no CLI in this build";
    for (const char* target : {"llvmpipe", "ipad1"}) {
        const std::string out = temp(std::string("bench-") + target + ".json");
        const std::string cmd = cli() + " bench " + DEPTHCULL_SOURCE_DIR + "/examples/meadow.json --no-cache -q --frames 0 --json --target " +
                                target + " -o " + out + " 2>" + temp("bench.err");
        const int rc = std::system(cmd.c_str());
        if (rc != 0 && slurp(temp("bench.err")).find("no OpenGL") != std::string::npos) GTEST_SKIP() << "no GL here";
        ASSERT_EQ(rc, 0) << slurp(temp("bench.err"));
        const nlohmann::json doc = nlohmann::json::parse(slurp(out));
        for (const auto& scene : doc["scenes"]) {
            // The limit's features, its blocks included (issue 25, docs/ideal-frame.md section 14).
            const auto& limit = scene["limit_features"];
            EXPECT_GT(limit["opaque_blocks"].get<long long>() + limit["blend_blocks"].get<long long>(), 0) << target;
            EXPECT_EQ(limit["rejected_fragments"].get<long long>(), 0) << target;
            for (const auto& mode : scene["modes"]) {
                EXPECT_EQ(mode["pixels_differ_elsewhere"].get<long long>(), 0) << target << " " << mode["mode"];
                EXPECT_GT(mode["predicted_ms"].get<double>(), 0) << target;
                // Each block a triangle shades holds a needed fragment or is waste.
                const auto& features = mode["model_features"];
                EXPECT_EQ(mode["blocks_by_texel"]["needed"].get<long long>() + mode["blocks_by_texel"]["waste"].get<long long>(),
                          features["opaque_blocks"].get<long long>() + features["blend_blocks"].get<long long>())
                    << target << " " << mode["mode"];
                // Overpaint draws every element as the limit's frame does.
                if (mode["mode"] == "overpaint") {
                    EXPECT_EQ(mode["blocks_by_texel"]["needed"].get<long long>(),
                              limit["opaque_blocks"].get<long long>() + limit["blend_blocks"].get<long long>())
                        << target;
                }
            }
        }
    }
}

// The per-element fallback (choose.cpp step 5) only keeps what predicts
// faster, so for every profile, including ones where opaque polygons or
// boundary edges cost more than they save, the output is predicted no
// slower than meshes only.
TEST(Target, NeverPredictedSlowerThanMeshesOnly) {
    if (cli().empty()) GTEST_SKIP() << "no CLI in this build";
    CostProfile base;
    ASSERT_TRUE(builtin_profile("llvmpipe", &base));
    CostProfile rejected_dear = base, edges_dear = base;
    rejected_dear.name = "rejected-dear";
    rejected_dear.fragment_rejected_ns = 10 * base.fragment_blend_ns;
    edges_dear.name = "edges-dear";
    edges_dear.triangle_perimeter_ns_per_pixel = 200;
    edges_dear.triangle_us = 20;
    std::vector<std::string> targets = {"llvmpipe", "ipad1"};
    for (const CostProfile& p : {rejected_dear, edges_dear}) {
        targets.push_back(temp(p.name + ".json"));
        pipeline::write_profile(targets.back(), p);
    }
    for (const std::string& target : targets) {
        const std::string err = temp("never-slower.err");
        const std::string cmd = cli() + " optimize " + DEPTHCULL_SOURCE_DIR + "/examples/meadow.json --no-cache --target " + target +
                                " -o " + temp("never-slower.json") + " 2>" + err;
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
        const std::string text = slurp(err);
        double predicted = 0, overpaint = 0, meshes = 0;
        const std::size_t at = text.find("predicted ");
        ASSERT_NE(at, std::string::npos) << text;
        ASSERT_EQ(std::sscanf(text.c_str() + at, "predicted %lf ms (overpaint %lf, meshes only %lf)", &predicted, &overpaint, &meshes), 3) << text;
        EXPECT_LE(predicted, meshes + 1e-9) << target << ": " << text;
    }
}

// The corpus package's Tiled map whose path ends in `tail` ("" if none).
std::string corpus_map(const char* package, const std::string& tail) {
    for (const std::string& p : test::corpus_files(package, ".tmx"))
        if (p.size() >= tail.size() && p.compare(p.size() - tail.size(), tail.size(), tail) == 0) return p;
    return {};
}

// Issue 25: on a ground of opaque tiles under buildings and trees with
// opaque cores (btanks' university), opaque polygons pay on llvmpipe only
// when what they hide is cut away, and the cuts' edges are priced in the
// choice: priced as free, the plan took every opaque polygon and lost more
// on edges than it saved (predicted slower, so none were drawn). Now some
// are, the frame stays pixel for pixel the overpaint's.
TEST(Target, OpaquePolygonsPayWhereTheirCutsPay) {
    if (cli().empty()) GTEST_SKIP() << "no CLI in this build";
    if (std::string why = test::corpus_missing("btanks-data"); !why.empty()) GTEST_SKIP() << why;
    const std::string map = corpus_map("btanks-data", "/university.tmx");
    ASSERT_FALSE(map.empty());
    const std::string err = temp("university.err"), out = temp("university.json");
    const std::string cmd = cli() + " optimize " + map + " --viewport 0,0,1024,768 --target llvmpipe --no-timing -o " + out + " 2>" + err;
    ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(err);
    const std::string text = slurp(err);
    const std::size_t at = text.find("opaque pass on, ");
    ASSERT_NE(at, std::string::npos) << text;
    long long opaque = 0;
    ASSERT_EQ(std::sscanf(text.c_str() + at, "opaque pass on, %lld elements with opaque polygons", &opaque), 1) << text;
    EXPECT_GT(opaque, 0) << text;
    const std::string bench = temp("university-bench.json");
    const int rc = std::system((cli() + " bench " + map + " --viewport 0,0,1024,768 --target llvmpipe -q --frames 0 --json -o " + bench +
                                " 2>" + err).c_str());
    if (rc != 0 && slurp(err).find("no OpenGL") != std::string::npos) GTEST_SKIP() << "no GL here";
    ASSERT_EQ(rc, 0) << slurp(err);
    const nlohmann::json doc = nlohmann::json::parse(slurp(bench)); // kept: the loop reads into it
    for (const auto& mode : doc["scenes"][0]["modes"]) EXPECT_EQ(mode["pixels_differ_elsewhere"].get<long long>(), 0) << mode["mode"];
}

// Issue 25's stages are options of the plan (PrepareOptions::clip_hidden,
// merge_opaque, cover_plan; --no-clip-hidden, --no-merge-opaque,
// --no-cover-plan), not environment
// switches: each turns its stage off in the plan and nothing else.
TEST(Target, StagesTurnOffByOption) {
    pipeline::PrepareOptions options;
    options.threads = 1;
    const pipeline::PreparedScene prepared = pipeline::prepare_scene(std::string(DEPTHCULL_SOURCE_DIR) + "/examples/meadow.json", options);
    CostProfile llvmpipe;
    ASSERT_TRUE(builtin_profile("llvmpipe", &llvmpipe));
    ASSERT_TRUE(clip_hidden_options(llvmpipe).enabled);
    for (int clip = 0; clip < 2; ++clip)
        for (int merge = 0; merge < 2; ++merge) {
            pipeline::PrepareOptions o = options;
            o.clip_hidden = clip;
            o.merge_opaque = merge;
            const pipeline::TargetPlan plan = pipeline::plan_target(prepared, o, llvmpipe, {});
            EXPECT_EQ(plan.reconstruct.clip_hidden.enabled, bool(clip)) << clip << merge;
            EXPECT_EQ(plan.reconstruct.merge_opaque, bool(merge)) << clip << merge;
        }
    pipeline::PrepareOptions with_depth = options;
    with_depth.depthless = false;
    EXPECT_FALSE(pipeline::plan_target(prepared, with_depth, llvmpipe, {}).reconstruct.depthless);
    // The cover plan (OpaqueMethod::cover's pieces) wins on the meadow for
    // the iPad's profile; --no-cover-plan keeps the default's polygons.
    CostProfile ipad1;
    ASSERT_TRUE(builtin_profile("ipad1", &ipad1));
    EXPECT_TRUE(pipeline::plan_target(prepared, options, ipad1, {}).opaque_cover);
    pipeline::PrepareOptions no_cover = options;
    no_cover.cover_plan = false;
    EXPECT_FALSE(pipeline::plan_target(prepared, no_cover, ipad1, {}).opaque_cover);
    if (cli().empty()) return;
    for (const char* command : {"optimize", "render", "bench", "report"}) {
        const std::string help = temp("stage-help.txt");
        ASSERT_EQ(std::system((cli() + " " + command + " --help >" + help).c_str()), 0) << command;
        const std::string text = slurp(help);
        EXPECT_NE(text.find("--no-clip-hidden"), std::string::npos) << command;
        EXPECT_NE(text.find("--no-merge-opaque"), std::string::npos) << command;
        EXPECT_NE(text.find("--no-cover-plan"), std::string::npos) << command;
        EXPECT_NE(text.find("--no-depthless"), std::string::npos) << command;
    }
    const std::string out = temp("stages-off.json");
    EXPECT_EQ(std::system((cli() + " optimize " + DEPTHCULL_SOURCE_DIR + "/examples/meadow.json --no-cache -q --target llvmpipe "
                           "--no-clip-hidden --no-merge-opaque --no-cover-plan --no-depthless -o " + out).c_str()), 0);
}

// Issue 25: a frame without a depth buffer (ReconstructOptions::depthless)
// where the plan predicts it faster: a tile map's ground of opaque tiles
// (Tiled's desert) needs no depth test at all. --no-depthless keeps the
// depth buffer; both draw the overpaint's pixels on the runtime.
TEST(Target, OpaqueTilesDrawWithoutADepthBuffer) {
    if (cli().empty()) GTEST_SKIP() << "no CLI in this build";
    if (std::string why = test::corpus_missing("tiled"); !why.empty()) GTEST_SKIP() << why;
    const std::string map = corpus_map("tiled", "/desert.tmx");
    ASSERT_FALSE(map.empty());
    for (const char* extra : {"", " --no-depthless"}) {
        const std::string err = temp("desert.err"), out = temp("desert.json");
        const std::string cmd = cli() + " optimize " + map + " --target llvmpipe --no-timing -o " + out + extra + " 2>" + err;
        ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(err);
        const bool depthless = *extra == '\0';
        EXPECT_EQ(slurp(err).find("; no depth buffer") != std::string::npos, depthless) << slurp(err);
        const nlohmann::json doc = nlohmann::json::parse(slurp(out));
        EXPECT_EQ(doc["depth_test"].get<bool>(), !depthless) << extra;
        bool opaque_pass = false;
        for (const auto& d : doc["draws"]) opaque_pass = opaque_pass || d["pass"] == "opaque";
        EXPECT_TRUE(opaque_pass) << extra; // the ground still draws without blending
        const std::string bench = temp("desert-bench.json");
        const int rc = std::system((cli() + " bench " + map + " --viewport 96,64,640,480 --target llvmpipe -q --frames 0 --json -o " + bench +
                                    extra + " 2>" + err).c_str());
        if (rc != 0 && slurp(err).find("no OpenGL") != std::string::npos) GTEST_SKIP() << "no GL here";
        ASSERT_EQ(rc, 0) << slurp(err);
        const nlohmann::json result = nlohmann::json::parse(slurp(bench));
        for (const auto& mode : result["scenes"][0]["modes"]) {
            EXPECT_EQ(mode["pixels_differ"].get<long long>(), 0) << mode["mode"] << extra;
        }
    }
}

// analyze --target: per image the chosen budget (or the plain rect) and
// MIN_OPAQUE_AREA from the profile, the same for any thread count.
TEST(Target, AnalyzeReportsThePerImageChoice) {
    if (cli().empty()) GTEST_SKIP() << "no CLI in this build";
    for (const char* target : {"llvmpipe", "ipad1"}) {
        std::string outputs[2];
        for (int k = 0; k < 2; ++k) {
            const std::string out = temp(std::string("analyze-") + target + std::to_string(k) + ".json");
            const std::string cmd = cli() + " analyze " + DEPTHCULL_SOURCE_DIR + "/examples/art --no-cache -q --no-timing -j " +
                                    std::to_string(k + 1) + " --target " + target + " -o " + out;
            ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
            outputs[k] = slurp(out);
        }
        EXPECT_EQ(outputs[0], outputs[1]) << target;
        CostProfile p;
        ASSERT_TRUE(builtin_profile(target, &p));
        const nlohmann::json doc = nlohmann::json::parse(outputs[0]);
        ASSERT_FALSE(doc["images"].empty());
        for (const auto& image : doc["images"]) {
            ASSERT_TRUE(image.contains("target")) << image["path"];
            const auto& t = image["target"];
            EXPECT_EQ(t["profile"], target);
            EXPECT_EQ(t["min_opaque_area"].get<int>(), min_opaque_area(p));
            const int budget = t["max_vertices"].get<int>();
            EXPECT_EQ(t["rect"].get<bool>(), budget == 0);
            EXPECT_TRUE(budget == 0 || budget == 4 || budget == 6 || budget == 8 || budget == 10) << budget;
            if (budget > 0) {
                for (const auto& poly : image["boundary"]) EXPECT_LE(int(poly.size()), budget) << image["path"];
            }
        }
    }
}

} // namespace
} // namespace depthcull

// ---- --target auto (issue 25): the GL renderer's profile, built in or
// calibrated once and cached with its renderer string.
#include <filesystem>

namespace depthcull {
namespace {

std::string fresh_dir(const std::string& name) {
    const std::string dir = temp(name);
    std::filesystem::remove_all(dir);
    return dir;
}

CostProfile measured_profile(double frame_us) {
    CostProfile p;
    EXPECT_TRUE(builtin_profile("llvmpipe", &p));
    p.name = "calibrated";
    p.frame_us = frame_us;
    return p;
}

TEST(AutoTarget, LlvmpipePicksTheBuiltInProfile) {
    const std::string renderer = "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6, EGL surfaceless";
    const std::string dir = fresh_dir("auto-builtin");
    const pipeline::AutoProfile found = pipeline::auto_profile(renderer, dir, [] {
        ADD_FAILURE() << "llvmpipe must not be calibrated";
        return CostProfile{};
    });
    EXPECT_EQ(found.profile.name, "llvmpipe");
    EXPECT_EQ(found.how, "built-in");
    EXPECT_FALSE(std::filesystem::exists(dir)); // nothing cached
    CostProfile p;
    EXPECT_FALSE(pipeline::builtin_profile_for_renderer("AMD Radeon RX 6600 (radeonsi, navi23, LLVM 15.0.6), OpenGL 4.6", &p));
}

TEST(AutoTarget, ACachedCalibrationIsReusedForItsRendererOnly) {
    const std::string dir = fresh_dir("auto-cache");
    const std::string acme = "Acme Tile GPU 9000, OpenGL 4.6 Acme 1.2, EGL device";
    int calibrations = 0;
    auto calibrate = [&] { return measured_profile(100 + ++calibrations); };
    const pipeline::AutoProfile first = pipeline::auto_profile(acme, dir, calibrate);
    EXPECT_EQ(calibrations, 1);
    EXPECT_EQ(first.how, "calibrated, cached in " + pipeline::profile_cache_path(dir, acme));
    EXPECT_EQ(first.profile.renderer, acme);
    const pipeline::AutoProfile again = pipeline::auto_profile(acme, dir, calibrate);
    EXPECT_EQ(calibrations, 1); // reused, not measured again
    EXPECT_EQ(again.how, "cached in " + pipeline::profile_cache_path(dir, acme));
    EXPECT_EQ(again.profile.frame_us, 101);
    EXPECT_EQ(again.profile.name, "calibrated");
    // Another renderer (a driver update changes the string) is measured for itself.
    const pipeline::AutoProfile other = pipeline::auto_profile(acme + " 2", dir, calibrate);
    EXPECT_EQ(calibrations, 2);
    EXPECT_EQ(other.profile.frame_us, 102);
    EXPECT_EQ(pipeline::auto_profile(acme, dir, calibrate).profile.frame_us, 101);
    // No cache directory: measured every time, nothing written.
    EXPECT_EQ(pipeline::auto_profile(acme, "", calibrate).how, "calibrated (not cached: no cache directory)");
    EXPECT_EQ(calibrations, 3);
}

// Decided: a cache entry that does not load is ours to replace, as the
// analysis cache's are, so it is measured again with a one-line warning
// naming the file (not an error the user must clear by hand).
TEST(AutoTarget, ACorruptCachedProfileIsMeasuredAgainWithOneWarning) {
    const std::string dir = fresh_dir("auto-corrupt");
    const std::string acme = "Acme Tile GPU 9000, OpenGL 4.6 Acme 1.2, EGL device";
    const std::string path = pipeline::profile_cache_path(dir, acme);
    int calibrations = 0;
    auto calibrate = [&] { return measured_profile(100 + ++calibrations); };
    std::vector<std::string> warnings;
    auto warn = [&](const std::string& line) { warnings.push_back(line); };
    pipeline::auto_profile(acme, dir, calibrate, warn);
    ASSERT_TRUE(warnings.empty());
    const std::string bad_files[] = {"{\"depthcull_profile\": 1, \"frame_us\": ", "not json at all", ""};
    for (const std::string& bad : bad_files) {
        warnings.clear();
        std::ofstream(path, std::ios::binary | std::ios::trunc) << bad;
        const int before = calibrations;
        const pipeline::AutoProfile found = pipeline::auto_profile(acme, dir, calibrate, warn);
        EXPECT_EQ(calibrations, before + 1) << bad;
        ASSERT_EQ(warnings.size(), 1u) << bad;
        EXPECT_EQ(warnings[0].find('\n'), std::string::npos);
        EXPECT_NE(warnings[0].find(path), std::string::npos) << warnings[0];
        EXPECT_NE(warnings[0].find("calibrating again"), std::string::npos) << warnings[0];
        EXPECT_EQ(pipeline::read_profile(path).frame_us, found.profile.frame_us); // replaced by a good one
    }
    // An entry measured on another renderer (a copied file) is not trusted either.
    CostProfile foreign = measured_profile(7);
    foreign.renderer = "Some Other GPU";
    pipeline::write_profile(path, foreign);
    warnings.clear();
    EXPECT_NE(pipeline::auto_profile(acme, dir, calibrate, warn).profile.frame_us, 7);
    EXPECT_EQ(warnings.size(), 1u);
}

TEST(AutoTarget, OnLlvmpipeTheCommandsUseTheBuiltInProfile) {
    if (cli().empty()) GTEST_SKIP() << "no CLI in this build";
    const std::string cache = fresh_dir("auto-xdg"), err = temp("auto.err");
    const std::string cmd = "XDG_CACHE_HOME=" + cache + " " + cli() + " optimize " + DEPTHCULL_SOURCE_DIR +
                            "/examples/meadow.json --no-cache --target auto -o " + temp("auto-meshes.json") + " 2>" + err;
    const int rc = std::system(cmd.c_str());
    const std::string text = slurp(err);
    if (rc != 0 && text.find("no OpenGL renderer found") != std::string::npos) GTEST_SKIP() << "no GL here";
    ASSERT_EQ(rc, 0) << text;
    if (text.find("llvmpipe (") == std::string::npos) GTEST_SKIP() << "not llvmpipe: " << text;
    EXPECT_NE(text.find("--target auto: llvmpipe ("), std::string::npos) << text;
    EXPECT_NE(text.find("profile llvmpipe (built-in)"), std::string::npos) << text;
    EXPECT_NE(text.find("--target llvmpipe: predicted"), std::string::npos) << text;
    EXPECT_FALSE(std::filesystem::exists(cache + "/depthcull/profiles")); // nothing calibrated
}

} // namespace
} // namespace depthcull
