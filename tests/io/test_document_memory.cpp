// Documents bounded by memory, each file read once (issue 21): small
// files whose parse would take gigabytes are refused by estimate before
// parsing (kMaxDocumentBytes); a template spelled many ways or a tileset
// named many times is parsed once per map; an atlas is written from the
// bytes it was read from. Each test failed before its fix.
#include <gtest/gtest.h>
#include <zlib.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "depthcull/io.h"
#include "depthcull/limits.h"
#include "io/formats.h"
#include "io/tiled_internal.h"

#include "testing/io_error.h"

namespace depthcull::test {
namespace {

namespace fs = std::filesystem;

struct Dir {
    fs::path root;
    explicit Dir(const std::string& name) : root(fs::temp_directory_path() / ("dc_docmem_" + name + "_" + std::to_string(::getpid()))) {
        fs::remove_all(root);
        fs::create_directories(root);
    }
    ~Dir() { fs::remove_all(root); }
    std::string write(const std::string& name, const std::string& bytes) const {
        fs::path p = root / name;
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << bytes;
        return p.string();
    }
    std::string write_gz(const std::string& name, const std::string& bytes) const {
        std::string p = (root / name).string();
        gzFile f = gzopen(p.c_str(), "wb1");
        gzwrite(f, bytes.data(), unsigned(bytes.size()));
        gzclose(f);
        return p;
    }
};

std::string repeat(const std::string& unit, std::size_t times) {
    std::string s;
    s.reserve(unit.size() * times);
    for (std::size_t i = 0; i < times; ++i) s += unit;
    return s;
}

// 80 MiB of "[]," in a Tiled JSON map, gzipped to a few hundred KB: about
// 1.3 GB once parsed by nlohmann (the issue's file holds 250 MiB of it and
// ran out of memory, then std::terminate in the destructor).
TEST(DocumentMemory, JsonMapOfEmptyArraysIsRefusedBeforeParsing) {
    Dir dir("tmj");
    std::string text = R"({"type":"map","width":1,"height":1,"tilewidth":8,"tileheight":8,"layers":[)" + repeat("[],", 28u << 20) +
                       "[]]}";
    std::string path = dir.write_gz("bomb.tmj.gz", text);
    text.clear();
    text.shrink_to_fit();
    std::string message = io_error([&] { io::read_scene(path); });
    EXPECT_TRUE(has(message, path + ": the JSON document would take about ")) << message;
    EXPECT_TRUE(has(message, "MiB of memory once parsed, more than the 1024 MiB (kMaxDocumentBytes)")) << message;
}

// 250 MiB of XML is within kMaxXmlBytes, but as "<a/>" a DOM of GiBs.
TEST(DocumentMemory, XmlMapOfEmptyElementsIsRefusedBeforeParsing) {
    Dir dir("tmx");
    std::string text = R"(<map version="1.10" orientation="orthogonal" width="1" height="1" tilewidth="8" tileheight="8">)" +
                       repeat("<a/>", 20u << 20) + "</map>";
    std::string path = dir.write_gz("bomb.tmx.gz", text);
    text.clear();
    text.shrink_to_fit();
    std::string message = io_error([&] { io::read_scene(path); });
    EXPECT_TRUE(has(message, path + ": the XML document would take about ")) << message;
    EXPECT_TRUE(has(message, "(kMaxDocumentBytes)")) << message;
}

TEST(DocumentMemory, EstimatesStayNearTheText) {
    // Ordinary documents: a few times their size, not refused.
    const std::string json = R"({"frames":{"a.png":{"frame":{"x":0,"y":0,"w":8,"h":8}}},"meta":{"image":"a.png","size":{"w":8,"h":8}}})";
    EXPECT_LT(io::json_document_bytes(json, "x"), 64 * json.size());
    EXPECT_GT(io::json_document_bytes(json, "x"), json.size());
    const std::string xml = R"(<map a="1" b="2"><layer name="x"><data encoding="csv">1,2,3</data></layer></map>)";
    EXPECT_EQ(io::xml_document_bytes(xml), xml.size() + 64 * 5 + 40 * 4); // the document, 3 elements, 1 text; 4 attributes
    // Comments, declarations and whitespace make no nodes.
    EXPECT_EQ(io::xml_document_bytes("<?xml version=\"1.0\"?>\n<!-- <a/><a/> -->\n<m>\n  </m>"),
              std::string("<?xml version=\"1.0\"?>\n<!-- <a/><a/> -->\n<m>\n  </m>").size() + 64 * 2);
}

// The peak resident memory of fn() run in a child, in KiB (-1: failed).
template <class F>
long child_peak_kib(F&& fn) {
    int fds[2];
    if (::pipe(fds) != 0) return -1;
    pid_t pid = ::fork();
    if (pid == 0) {
        ::close(fds[0]);
        long peak = -1;
        try {
            fn();
            rusage usage{};
            ::getrusage(RUSAGE_SELF, &usage);
            peak = usage.ru_maxrss;
        } catch (...) {
        }
        (void)!::write(fds[1], &peak, sizeof peak);
        ::_exit(0);
    }
    ::close(fds[1]);
    long peak = -1;
    if (::read(fds[0], &peak, sizeof peak) != sizeof peak) peak = -1;
    ::close(fds[0]);
    ::waitpid(pid, nullptr, 0);
    return peak;
}

// A template of 2M extra elements (about 130 MB as a DOM) spelled 8 ways
// across 2 object layers: before, 8 documents were held at once (> 1 GB).
TEST(DocumentMemory, TemplateSpelledManyWaysIsParsedOnce) {
    Dir dir("tx");
    dir.write("bomb.tx", R"(<template><object width="8" height="8"/>)" + repeat("<p/>", 2u << 20) + "</template>");
    fs::create_directories(dir.root / "sub");
    fs::create_symlink(dir.root / "bomb.tx", dir.root / "link.tx");
    auto map_with = [&](const std::vector<std::string>& spellings) {
        std::string layers;
        int id = 1;
        for (int layer = 0; layer < 2; ++layer) {
            layers += "<objectgroup name=\"o" + std::to_string(layer) + "\">";
            for (const std::string& s : spellings) layers += "<object id=\"" + std::to_string(id++) + "\" template=\"" + s + "\"/>";
            layers += "</objectgroup>";
        }
        return dir.write("map.tmx", R"(<map orientation="orthogonal" width="1" height="1" tilewidth="8" tileheight="8">)" + layers + "</map>");
    };
    const std::string once = map_with({"bomb.tx"});
    const long one = child_peak_kib([&] { io::read_scene(once); });
    const std::string many = map_with({"bomb.tx", "./bomb.tx", "././bomb.tx", "sub/../bomb.tx", "./sub/../bomb.tx", "link.tx", ".//bomb.tx",
                                       "sub/.././bomb.tx"});
    const long eight = child_peak_kib([&] { io::read_scene(many); });
    ASSERT_GT(one, 0);
    ASSERT_GT(eight, 0);
    // One document is > 100 MB; eight would add 7 of them.
    EXPECT_LT(eight, one + 100 * 1024) << "peak KiB, 1 spelling: " << one << ", 8 spellings: " << eight;
}

// Parsed once and held once, however many <tileset> elements name it.
TEST(DocumentMemory, TilesetNamedManyTimesIsParsedOnce) {
    Dir dir("tsx");
    std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x10\0\0\0\x10\x08\x06\0\0\0", 29);
    dir.write("a.png", png + std::string(8, '\0'));
    dir.write("t.tsx", R"(<tileset name="t" tilewidth="8" tileheight="8"><image source="a.png" width="16" height="16"/></tileset>)");
    fs::create_symlink(dir.root / "t.tsx", dir.root / "u.tsx");
    pugi::xml_document doc;
    std::string map = R"(<map><tileset firstgid="1" source="t.tsx"/><tileset firstgid="5" source="./t.tsx"/><tileset firstgid="9" source="u.tsx"/></map>)";
    ASSERT_TRUE(doc.load_string(map.c_str()));
    std::vector<SceneImage> images;
    io::tiled::ImageTable table(images);
    std::vector<io::tiled::Tileset> tilesets = io::tiled::read_tilesets(doc.child("map"), (dir.root / "m.tmx").string(), table);
    ASSERT_EQ(tilesets.size(), 3u);
    EXPECT_EQ(tilesets[0].tables, tilesets[1].tables);
    EXPECT_EQ(tilesets[0].tables, tilesets[2].tables);
    EXPECT_EQ(tilesets[2].firstgid, 9u);
    EXPECT_EQ(images.size(), 1u);
}

// The atlas file replaced after it was read: the polygons are written from
// the bytes read (before, the file was parsed again and its frames indexed
// with the old ones: SIGSEGV with more frames).
TEST(DocumentMemory, AtlasPolygonsAreWrittenFromTheBytesRead) {
    Dir dir("atlas");
    std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x10\0\0\0\x10\x08\x06\0\0\0", 29);
    dir.write("page.png", png);
    auto frame = [](const std::string& name) {
        return "\"" + name + R"(": {"frame": {"x":0,"y":0,"w":8,"h":8}, "rotated": false, "trimmed": false, "spriteSourceSize": {"x":0,"y":0,"w":8,"h":8}, "sourceSize": {"w":8,"h":8}})";
    };
    const std::string path = dir.write("a.json", "{\"frames\": {" + frame("one") + "}, \"meta\": {\"image\": \"page.png\"}}");
    io::Atlas atlas = io::read_atlas(path);
    std::string frames = frame("x0");
    for (int i = 1; i < 1000; ++i) frames += "," + frame("x" + std::to_string(i));
    dir.write("a.json", "{\"frames\": {" + frames + "}, \"meta\": {\"image\": \"page.png\"}}");
    std::vector<ImageAnalysis> analyses(atlas.frames.size());
    std::string text = io::atlas_polygons_json(path, atlas, analyses);
    EXPECT_TRUE(has(text, "\"one\"")) << text.substr(0, 200);
    EXPECT_FALSE(has(text, "\"x999\""));
    // A hand-made Atlas has no bytes: the file is read, and must match.
    atlas.text.reset();
    EXPECT_TRUE(has(io_error([&] { io::atlas_polygons_json(path, atlas, analyses); }), "differ from the atlas read"));
}

// The mesh readers refuse a stats.depth_levels the draws contradict
// (issue 21): add_dynamic_elements and engines put new sprites above it.
TEST(DocumentMemory, MeshReadersRefuseDepthLevelsTheDrawsContradict) {
    auto mesh = [](const std::string& levels) {
        return R"({"viewport": {"x": 0, "y": 0, "width": 8, "height": 8}, "depth_test": true, "images": [{"id": "a", "path": "a.png", "width": 4, "height": 4}], "draws": [{"image": "a", "pass": "blend", "blend": "alpha", "vertices": [0, 0, 0.5, 0, 0, 1, 1, 1, 1, 4, 0, 0.5, 1, 0, 1, 1, 1, 1, 0, 4, 0.5, 0, 1, 1, 1, 1, 1], "indices": [0, 1, 2]}], "stats": {"elements": 1, "draw_calls": 1, "triangles": 1, "depth_levels": )" +
               levels + R"(, "depth_bits": 10, "graph_edges": 0, "seconds": 0}})";
    };
    io::MeshesDocument good = io::meshes_from_json(mesh("64"), "m.json");
    EXPECT_EQ(good.meshes.stats.depth_levels, 64);
    EXPECT_TRUE(has(io_error([&] { io::meshes_from_json(mesh("1"), "m.json"); }), "m.json: stats depth_levels 1 is lower than the 64 levels"));
    EXPECT_TRUE(has(io_error([&] { io::meshes_from_json(mesh("9223372036854775807"), "m.json"); }), "more than the depth mapping resolves"));
    good.meshes.stats.depth_levels = 2;
    const std::string binary = io::meshes_to_binary(good, "");
    EXPECT_TRUE(has(io_error([&] { io::meshes_from_binary(binary, "m.bin"); }), "m.bin: stats depth_levels 2 is lower than the 64 levels"));
}

} // namespace
} // namespace depthcull::test
