// Cost profiles as JSON files (the format of docs/cost-model.md), in
// pipeline because io depends on no cost type; the JSON checks are io's.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "depthcull/target.h"

namespace depthcull::pipeline {

using depthcull::Error;

namespace {

using nlohmann::json;

struct Term {
    const char* key;
    double CostProfile::*field;
};
constexpr Term kTerms[] = {
    {"frame_us", &CostProfile::frame_us},
    {"clear_color_ns_per_pixel", &CostProfile::clear_color_ns_per_pixel},
    {"clear_depth_ns_per_pixel", &CostProfile::clear_depth_ns_per_pixel},
    {"draw_call_us", &CostProfile::draw_call_us},
    {"texture_switch_us", &CostProfile::texture_switch_us},
    {"triangle_us", &CostProfile::triangle_us},
    {"triangle_perimeter_ns_per_pixel", &CostProfile::triangle_perimeter_ns_per_pixel},
    {"fragment_opaque_ns", &CostProfile::fragment_opaque_ns},
    {"fragment_blend_ns", &CostProfile::fragment_blend_ns},
    {"fragment_rejected_ns", &CostProfile::fragment_rejected_ns},
};

} // namespace

CostProfile profile_from_json(const std::string& text, const std::string& name) {
    io::check_json_document(text, name);
    json j;
    try {
        j = json::parse(text);
    } catch (const std::exception& e) { // nlohmann's, or std::bad_alloc ("out of memory")
        io::throw_json_error(e, text, name);
    }
    if (!j.is_object()) throw Error(name + ": a profile is a JSON object");
    CostProfile p;
    if (!j.contains("depthcull_profile") || !j["depthcull_profile"].is_number_integer() || j["depthcull_profile"].get<long long>() != 1)
        throw Error(name + ": \"depthcull_profile\": expected 1 (the profile format version)");
    for (const char* s : {"name", "renderer", "source"}) {
        if (!j.contains(s)) continue;
        if (!j[s].is_string()) throw Error(name + ": \"" + s + "\": expected a string");
    }
    p.name = j.value("name", std::string());
    p.renderer = j.value("renderer", std::string());
    p.source = j.value("source", std::string());
    for (const Term& t : kTerms) {
        if (!j.contains(t.key)) throw Error(name + ": \"" + t.key + "\" missing (every term of the model is required)");
        const json& v = j[t.key];
        if (!v.is_number()) throw Error(name + ": \"" + t.key + "\": expected a number");
        const double d = v.get<double>();
        if (!std::isfinite(d) || d < 0) throw Error(name + ": \"" + t.key + "\": " + v.dump() + " is not a finite number >= 0");
        p.*t.field = d;
    }
    for (const auto& [key, value] : j.items()) {
        bool known = key == "depthcull_profile" || key == "name" || key == "renderer" || key == "source" || key == "wall" ||
                     key == "min_opaque_area";
        for (const Term& t : kTerms) known = known || key == t.key;
        if (!known) throw Error(name + ": \"" + key + "\": unknown key");
    }
    return p;
}

std::string profile_to_json(const CostProfile& p) {
    // Keys in the model's order, so a profile reads top to bottom.
    std::ostringstream out;
    out << "{\n  \"depthcull_profile\": 1,\n";
    out << "  \"name\": " << json(p.name).dump() << ",\n";
    out << "  \"renderer\": " << json(p.renderer).dump() << ",\n";
    out << "  \"source\": " << json(p.source).dump() << ",\n";
    for (std::size_t i = 0; i < std::size(kTerms); ++i)
        out << "  \"" << kTerms[i].key << "\": " << json(p.*kTerms[i].field).dump() << ",\n";
    out << "  \"min_opaque_area\": " << min_opaque_area(p) << "\n}\n";
    return out.str();
}

CostProfile read_profile(const std::string& path) { return profile_from_json(io::read_file(path), path); }

void write_profile(const std::string& path, const CostProfile& profile) { io::write_file_atomic(path, profile_to_json(profile)); }

CostProfile resolve_target(const std::string& name_or_path) {
    CostProfile p;
    if (builtin_profile(name_or_path, &p)) return p;
    if (name_or_path.find('/') == std::string::npos && name_or_path.find('.') == std::string::npos) {
        std::string names;
        for (const std::string& n : builtin_profile_names()) names += (names.empty() ? "" : ", ") + n;
        throw Error("--target: '" + name_or_path + "' is neither a built-in profile (" + names + ") nor a profile file");
    }
    return read_profile(name_or_path);
}

std::vector<Table2Row> read_table2_tsv(const std::string& path) {
    std::istringstream in(io::read_file(path));
    std::vector<Table2Row> rows;
    int line_no = 0;
    bool header = false;
    for (std::string line; std::getline(in, line);) {
        ++line_no;
        if (line.empty() || line[0] == '#') continue;
        if (!header) {
            header = true;
            continue;
        }
        std::istringstream f(line);
        Table2Row r;
        if (!(std::getline(f, r.scene, '\t') && std::getline(f, r.mode, '\t') && (f >> r.objects >> r.triangles >> r.overdraw >> r.fps)))
            throw Error(path + ": line " + std::to_string(line_no) + ": expected scene, mode, obj, tri, od, fps");
        rows.push_back(r);
    }
    return rows;
}

std::size_t choose_image_candidate(const std::vector<const ImageAnalysis*>& candidates, const CostProfile& p) {
    std::size_t best = 0;
    double best_ns = INFINITY;
    for (std::size_t c = 0; c < candidates.size(); ++c) {
        const ImageAnalysis* a = candidates[c];
        if (!a) continue;
        double ns = 0;
        for (const Polygon& poly : a->boundary) {
            const std::vector<std::uint32_t> tri = triangulate_polygon(poly);
            for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
                ns += p.triangle_us * 1e3;
                for (int k = 0; k < 3; ++k) {
                    const Vec2 &u = poly[tri[t + std::size_t(k)]], &v = poly[tri[t + std::size_t((k + 1) % 3)]];
                    ns += p.triangle_perimeter_ns_per_pixel * std::hypot(v.x - u.x, v.y - u.y);
                }
            }
        }
        ns += p.fragment_blend_ns * a->stats.boundary_area;
        if (ns < best_ns) best_ns = ns, best = c;
    }
    return best;
}

} // namespace depthcull::pipeline
