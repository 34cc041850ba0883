#pragma once
// What the io-layer tests ask of a failure: the one-line message of the
// depthcull::Error a call throws, and whether a message says a given thing.

#include <exception>
#include <string>

#include <gtest/gtest.h>

#include "depthcull/io.h"

namespace depthcull::test {

// The message of the depthcull::Error that fn throws; fails the test when it
// throws anything else or nothing.
template <class F>
std::string io_error(F&& fn) {
    try {
        fn();
    } catch (const depthcull::Error& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not a depthcull::Error: " << e.what();
        return {};
    }
    ADD_FAILURE() << "no error";
    return {};
}

inline bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

} // namespace depthcull::test
