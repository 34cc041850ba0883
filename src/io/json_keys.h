// Reading a JSON document's object keys, with their nesting depth, without
// building it: a SAX pass (nlohmann's parser is iterative, so depth costs
// no stack). Callers decide what a key means (read_scene.cpp: is a .json
// file a Tiled map; texturepacker.cpp: the hash form's frame order).
#pragma once

#include <string_view>

#include <nlohmann/json.hpp>

namespace depthcull::io {

// on_key(depth, key) for every key, depth 1 for the top-level object's;
// returning false stops the pass. Values are skipped; a syntax error just
// ends the pass (the real parse reports it).
template <class OnKey>
void scan_json_keys(std::string_view text, OnKey&& on_key) {
    struct Keys final : nlohmann::json_sax<nlohmann::json> {
        OnKey& on_key;
        int depth = 0;
        explicit Keys(OnKey& f) : on_key(f) {}
        bool null() override { return true; }
        bool boolean(bool) override { return true; }
        bool number_integer(number_integer_t) override { return true; }
        bool number_unsigned(number_unsigned_t) override { return true; }
        bool number_float(number_float_t, const string_t&) override { return true; }
        bool string(string_t&) override { return true; }
        bool binary(binary_t&) override { return true; }
        bool start_object(std::size_t) override { return ++depth, true; }
        bool end_object() override { return --depth, true; }
        bool start_array(std::size_t) override { return ++depth, true; }
        bool end_array() override { return --depth, true; }
        bool key(string_t& k) override { return on_key(depth, std::string_view(k)); }
        bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }
    } keys(on_key);
    nlohmann::json::sax_parse(text, &keys);
}

} // namespace depthcull::io
