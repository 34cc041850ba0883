// Reads the meshes JSON (docs/mesh-format.md) back into SceneMeshes. Errors
// name the JSON path of the bad value ("draws[3].indices[7]"). Floats are
// read as doubles and rounded to float once: the writer's shortest float
// text (at most 9 digits) reads back as the float it was written from
// (tests/io/test_mesh_readers.cpp checks it over random bit patterns).
#include <cfloat>
#include <map>

#include <nlohmann/json.hpp>

#include "depthcull/io.h"
#include "io/formats.h"
#include "io/mesh_common.h"

namespace depthcull::io {

namespace {

using nlohmann::json;

struct Context {
    const std::string& name;
    [[noreturn]] void fail(const std::string& where, const std::string& what) const {
        throw Error(name + ": " + where + ": " + what);
    }
};

std::string at(const std::string& where, std::size_t i) { return where + "[" + std::to_string(i) + "]"; }
std::string at(const std::string& where, const char* key) { return where.empty() ? key : where + "." + key; }

const json& field(const Context& ctx, const json& obj, const std::string& where, const char* key) {
    auto it = obj.find(key);
    if (it == obj.end()) ctx.fail(where.empty() ? "top level" : where, std::string("missing \"") + key + "\"");
    return *it;
}

const json& object(const Context& ctx, const json& v, const std::string& where) {
    if (!v.is_object()) ctx.fail(where, "must be an object");
    return v;
}

const json& array(const Context& ctx, const json& v, const std::string& where, std::size_t max) {
    if (!v.is_array()) ctx.fail(where, "must be an array");
    if (v.size() > max) ctx.fail(where, "has more than " + std::to_string(max) + " entries");
    return v;
}

double number(const Context& ctx, const json& v, const std::string& where) {
    if (!v.is_number()) ctx.fail(where, "must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) ctx.fail(where, "must be finite");
    return d;
}

std::int64_t integer(const Context& ctx, const json& v, const std::string& where, std::int64_t max) {
    if (v.is_number_unsigned() && v.get<std::uint64_t>() <= std::uint64_t(max)) return std::int64_t(v.get<std::uint64_t>());
    if (v.is_number_integer() && v.get<std::int64_t>() >= 0 && v.get<std::int64_t>() <= max) return v.get<std::int64_t>();
    ctx.fail(where, "must be an integer in 0.." + std::to_string(max));
}

const std::string& string(const Context& ctx, const json& v, const std::string& where) {
    if (!v.is_string()) ctx.fail(where, "must be a string");
    const auto& s = v.get_ref<const std::string&>();
    if (s.size() > kMaxMeshStringBytes) ctx.fail(where, "is longer than " + std::to_string(kMaxMeshStringBytes) + " bytes");
    return s;
}

Viewport read_viewport(const Context& ctx, const json& v) {
    object(ctx, v, "viewport");
    Viewport vp;
    vp.x = number(ctx, field(ctx, v, "viewport", "x"), "viewport.x");
    vp.y = number(ctx, field(ctx, v, "viewport", "y"), "viewport.y");
    vp.width = int(integer(ctx, field(ctx, v, "viewport", "width"), "viewport.width", INT32_MAX));
    vp.height = int(integer(ctx, field(ctx, v, "viewport", "height"), "viewport.height", INT32_MAX));
    return vp;
}

SceneImage read_image_entry(const Context& ctx, const json& v, const std::string& where, const std::string& base_dir) {
    object(ctx, v, where);
    SceneImage img;
    img.id = string(ctx, field(ctx, v, where, "id"), at(where, "id"));
    img.path = resolve_mesh_path(base_dir, string(ctx, field(ctx, v, where, "path"), at(where, "path")));
    img.width = int(integer(ctx, field(ctx, v, where, "width"), at(where, "width"), kMaxImageSide));
    img.height = int(integer(ctx, field(ctx, v, where, "height"), at(where, "height"), kMaxImageSide));
    if (v.contains("trans")) {
        img.has_trans = true;
        img.trans = parse_color_key(string(ctx, v["trans"], at(where, "trans")), ctx.name + ": " + at(where, "trans"));
    }
    if (v.contains("fill")) {
        img.has_fill = true;
        img.fill = parse_color_key(string(ctx, v["fill"], at(where, "fill")), ctx.name + ": " + at(where, "fill"));
        img.path.clear();
    }
    return img;
}

Blend read_blend(const Context& ctx, const json& v, const std::string& where) {
    const std::string& s = string(ctx, v, where);
    for (Blend b : {Blend::alpha, Blend::add, Blend::multiply, Blend::opaque})
        if (s == blend_name(b)) return b;
    ctx.fail(where, "unknown blend \"" + s + "\" (expected alpha, add, multiply or opaque)");
}

struct Totals {
    std::size_t vertices = 0, indices = 0;
};

std::vector<float> read_vertices(const Context& ctx, const json& v, const std::string& where, Totals* totals) {
    array(ctx, v, where, kMaxMeshVertices * kVertexFloats);
    if (v.size() % kVertexFloats) ctx.fail(where, "has " + std::to_string(v.size()) + " numbers, not 9 per vertex");
    const std::size_t count = v.size() / kVertexFloats;
    if (count > kMaxMeshVertices - totals->vertices) ctx.fail(where, "more than " + std::to_string(kMaxMeshVertices) + " vertices in all draws");
    totals->vertices += count;
    std::vector<float> out(v.size());
    for (std::size_t k = 0; k < out.size(); ++k) {
        const double d = number(ctx, v[k], at(where, k));
        if (std::fabs(d) > FLT_MAX) ctx.fail(at(where, k), "is outside the range of a float");
        out[k] = float(d);
        if (const char* problem = vertex_float_problem(k, out[k])) ctx.fail(at(where, k), problem);
    }
    return out;
}

std::vector<std::uint32_t> read_indices(const Context& ctx, const json& v, const std::string& where, std::size_t vertex_count, Totals* totals) {
    array(ctx, v, where, kMaxMeshIndices);
    if (v.size() % 3) ctx.fail(where, "has " + std::to_string(v.size()) + " indices, not a multiple of 3 (triangles)");
    if (v.size() > kMaxMeshIndices - totals->indices) ctx.fail(where, "more than " + std::to_string(kMaxMeshIndices) + " indices in all draws");
    totals->indices += v.size();
    std::vector<std::uint32_t> out(v.size());
    for (std::size_t k = 0; k < out.size(); ++k) {
        if (vertex_count == 0) ctx.fail(at(where, k), "an index into a draw without vertices");
        out[k] = std::uint32_t(integer(ctx, v[k], at(where, k), std::int64_t(vertex_count) - 1));
    }
    return out;
}

Draw read_draw(const Context& ctx, const json& v, const std::string& where, const std::map<std::string, int>& ids, Totals* totals) {
    object(ctx, v, where);
    Draw d;
    const std::string& id = string(ctx, field(ctx, v, where, "image"), at(where, "image"));
    auto it = ids.find(id);
    if (it == ids.end()) ctx.fail(at(where, "image"), "unknown image id \"" + id + "\"");
    d.image = it->second;
    const std::string& pass = string(ctx, field(ctx, v, where, "pass"), at(where, "pass"));
    if (pass != "opaque" && pass != "blend") ctx.fail(at(where, "pass"), "unknown pass \"" + pass + "\" (expected opaque or blend)");
    d.pass = pass == "opaque" ? Pass::opaque : Pass::blend;
    d.blend = read_blend(ctx, field(ctx, v, where, "blend"), at(where, "blend"));
    d.vertices = read_vertices(ctx, field(ctx, v, where, "vertices"), at(where, "vertices"), totals);
    d.indices = read_indices(ctx, field(ctx, v, where, "indices"), at(where, "indices"), d.vertex_count(), totals);
    return d;
}

// "animations" and "animated" (docs/mesh-format.md): frames of one size
// naming existing images, runs inside their draw's vertices naming
// existing animations.
void read_animations(const Context& ctx, const json& doc, MeshesDocument* out) {
    if (doc.contains("animations")) {
        const json& animations = array(ctx, doc["animations"], "animations", kMaxMeshAnimations);
        out->animations.reserve(animations.size());
        for (std::size_t i = 0; i < animations.size(); ++i) {
            const std::string where = at("animations", i);
            object(ctx, animations[i], where);
            const json& frames = array(ctx, field(ctx, animations[i], where, "frames"), at(where, "frames"), kMaxMeshAnimationFrames);
            if (frames.empty()) ctx.fail(at(where, "frames"), "has no frames");
            Animation animation;
            animation.frames.reserve(frames.size());
            for (std::size_t k = 0; k < frames.size(); ++k) {
                const std::string fw = at(at(where, "frames"), k);
                object(ctx, frames[k], fw);
                AnimationFrame f;
                if (out->images.empty()) ctx.fail(at(fw, "image"), "names an image but there are none");
                f.image = int(integer(ctx, field(ctx, frames[k], fw, "image"), at(fw, "image"), std::int64_t(out->images.size()) - 1));
                const json& rect = field(ctx, frames[k], fw, "rect");
                if (!rect.is_array() || rect.size() != 4) ctx.fail(at(fw, "rect"), "must be [x, y, w, h]");
                f.rect.x = int(integer(ctx, rect[0], at(at(fw, "rect"), std::size_t(0)), kMaxImageSide));
                f.rect.y = int(integer(ctx, rect[1], at(at(fw, "rect"), std::size_t(1)), kMaxImageSide));
                f.rect.w = int(integer(ctx, rect[2], at(at(fw, "rect"), std::size_t(2)), kMaxImageSide));
                f.rect.h = int(integer(ctx, rect[3], at(at(fw, "rect"), std::size_t(3)), kMaxImageSide));
                if (f.rect.empty()) ctx.fail(at(fw, "rect"), "is empty");
                if (k && (f.rect.w != animation.frames[0].rect.w || f.rect.h != animation.frames[0].rect.h))
                    ctx.fail(at(fw, "rect"), "is not the size of frame 0's");
                f.duration_ms = int(integer(ctx, field(ctx, frames[k], fw, "duration"), at(fw, "duration"), INT32_MAX));
                animation.frames.push_back(f);
            }
            out->animations.push_back(std::move(animation));
        }
    }
    if (doc.contains("animated")) {
        const auto& draws = out->meshes.draws;
        const json& runs = array(ctx, doc["animated"], "animated", kMaxMeshVertices);
        out->animated.reserve(runs.size());
        for (std::size_t i = 0; i < runs.size(); ++i) {
            const std::string where = at("animated", i);
            object(ctx, runs[i], where);
            AnimatedRun r;
            if (draws.empty()) ctx.fail(at(where, "draw"), "names a draw but there are none");
            r.draw = std::uint32_t(integer(ctx, field(ctx, runs[i], where, "draw"), at(where, "draw"), std::int64_t(draws.size()) - 1));
            const std::int64_t vertices = std::int64_t(draws[r.draw].vertex_count());
            if (vertices == 0) ctx.fail(at(where, "draw"), "names a draw without vertices");
            r.first_vertex = std::uint32_t(integer(ctx, field(ctx, runs[i], where, "first_vertex"), at(where, "first_vertex"), vertices - 1));
            r.vertex_count = std::uint32_t(integer(ctx, field(ctx, runs[i], where, "vertex_count"), at(where, "vertex_count"), vertices - r.first_vertex));
            if (r.vertex_count == 0) ctx.fail(at(where, "vertex_count"), "must not be 0");
            if (out->animations.empty()) ctx.fail(at(where, "animation"), "names an animation but there are none");
            r.animation = std::uint32_t(integer(ctx, field(ctx, runs[i], where, "animation"), at(where, "animation"), std::int64_t(out->animations.size()) - 1));
            if (!out->animated.empty() && r.draw < out->animated.back().draw) ctx.fail(at(where, "draw"), "runs are not in draw order");
            out->animated.push_back(r);
        }
    }
}

// The stats, and stats.seconds (MeshesDocument::seconds) beside them.
SceneStats read_stats(const Context& ctx, const json& v, double* seconds) {
    object(ctx, v, "stats");
    SceneStats st;
    const std::pair<const char*, std::int64_t*> counts[] = {{"elements", &st.elements},         {"draw_calls", &st.draw_calls},
                                                            {"triangles", &st.triangles},       {"depth_levels", &st.depth_levels},
                                                            {"depth_bits", &st.depth_bits},     {"graph_edges", &st.graph_edges}};
    for (const auto& [key, value] : counts)
        if (v.contains(key)) *value = integer(ctx, v[key], at("stats", key), INT64_MAX);
    if (v.contains("seconds")) {
        *seconds = number(ctx, v["seconds"], "stats.seconds");
        if (*seconds < 0) ctx.fail("stats.seconds", "must not be negative");
    }
    return st;
}

// "insertion_points" (docs/mesh-format.md): after the draws and stats,
// which they are checked against.
void read_insertion_points(const Context& ctx, const json& doc, SceneMeshes* m) {
    if (!doc.contains("insertion_points")) return;
    const json& points = array(ctx, doc["insertion_points"], "insertion_points", kMaxMeshInsertionPoints);
    m->insertion_points.reserve(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
        const std::string where = at("insertion_points", k);
        object(ctx, points[k], where);
        InsertionPoint p;
        p.element = std::size_t(integer(ctx, field(ctx, points[k], where, "element"), at(where, "element"), INT64_MAX));
        p.levels = integer(ctx, field(ctx, points[k], where, "levels"), at(where, "levels"), kMaxDepthLevels);
        p.first_level = integer(ctx, field(ctx, points[k], where, "first_level"), at(where, "first_level"), kMaxDepthLevels);
        p.blend_draw = std::uint32_t(integer(ctx, field(ctx, points[k], where, "blend_draw"), at(where, "blend_draw"), UINT32_MAX));
        m->insertion_points.push_back(p);
        const char* key = "";
        if (std::string problem = insertion_point_problem(*m, k, &key); !problem.empty()) ctx.fail(at(where, key), problem);
    }
    if (std::string problem = insertion_levels_problem(*m); !problem.empty()) ctx.fail("insertion_points", problem);
}

MeshesDocument read_json(std::string_view text, const std::string& name, const std::string& base_dir) {
    const Context ctx{name};
    json doc;
    // Deep nesting would overflow the parser's stack: refuse it first.
    check_json_depth(text, name);
    try {
        doc = json::parse(text);
    } catch (const json::exception& e) { // parse_error; out_of_range for numbers like 1e400
        throw_json_error(e, text, name); // byte offsets from 0, as the binary reader's
    }
    if (!doc.is_object()) ctx.fail("top level", "expected a JSON object with \"images\" and \"draws\"");
    MeshesDocument out;
    out.meshes.viewport = read_viewport(ctx, field(ctx, doc, "", "viewport"));
    const json& depth_test = field(ctx, doc, "", "depth_test");
    if (!depth_test.is_boolean()) ctx.fail("depth_test", "must be true or false");
    out.meshes.depth_test = depth_test.get<bool>();
    if (doc.contains("filter")) { // absent in files written before it was: nearest
        const json& filter = doc["filter"];
        if (filter != "nearest" && filter != "linear") ctx.fail("filter", "must be \"nearest\" or \"linear\"");
        out.meshes.filter = filter == "linear" ? Filter::linear : Filter::nearest;
    }

    const json& images = array(ctx, field(ctx, doc, "", "images"), "images", kMaxMeshImages);
    std::map<std::string, int> ids; // a draw names the first entry with its id
    out.images.reserve(images.size());
    for (std::size_t i = 0; i < images.size(); ++i) {
        out.images.push_back(read_image_entry(ctx, images[i], at("images", i), base_dir));
        ids.emplace(out.images.back().id, int(i));
    }
    const json& draws = array(ctx, field(ctx, doc, "", "draws"), "draws", kMaxMeshDraws);
    out.meshes.draws.reserve(draws.size());
    Totals totals;
    for (std::size_t i = 0; i < draws.size(); ++i) out.meshes.draws.push_back(read_draw(ctx, draws[i], at("draws", i), ids, &totals));
    if (doc.contains("stats")) out.meshes.stats = read_stats(ctx, doc["stats"], &out.seconds);
    read_animations(ctx, doc, &out);
    out.meshes.depth_denominator = depth_denominator_from_bits(out.meshes.stats.depth_bits);
    check_depth_levels(out.meshes, name);
    read_insertion_points(ctx, doc, &out.meshes);
    return out;
}

} // namespace

MeshesDocument meshes_from_json(std::string_view text, const std::string& name, const std::string& base_dir) {
    return guarded(name, [&] { return read_json(text, name, base_dir); });
}

} // namespace depthcull::io
