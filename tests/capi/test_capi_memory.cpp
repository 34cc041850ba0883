// dc_meshes_read_memory over a document whose parse would take gigabytes
// (issue 21): a status and a message, not std::bad_alloc and then
// std::terminate in nlohmann's destructor, which took the host down.
#include <gtest/gtest.h>

#include <string>

#include "depthcull/depthcull.h"

namespace {

TEST(CapiMemory, HugeJsonDocumentIsAStatus) {
    std::string text = "{\"meshes\":[";
    text.reserve(text.size() + 3 * (std::size_t(28) << 20) + 4);
    for (std::size_t i = 0; i < (std::size_t(28) << 20); ++i) text += "[],";
    text += "[]]}";
    dc_meshes* meshes = nullptr;
    EXPECT_EQ(dc_meshes_read_memory(text.data(), text.size(), nullptr, &meshes), DC_ERROR_IO);
    EXPECT_EQ(meshes, nullptr);
    const std::string message = dc_last_error();
    EXPECT_NE(message.find("(kMaxDocumentBytes)"), std::string::npos) << message;
}

} // namespace
