// The real-game corpus fetched by scripts/fetch-corpus. Tests that need it
// call GTEST_SKIP() with the message from corpus_missing() when absent.
#pragma once

#include <string>
#include <vector>

namespace depthcull::test {

// $DEPTHCULL_CORPUS, else $XDG_CACHE_HOME/depthcull/corpus, else
// ~/.cache/depthcull/corpus.
std::string corpus_dir();
// Empty when the package's tree is present, else a skip message.
std::string corpus_missing(const std::string& package);
// Sorted paths of files under corpus_dir()/package whose names end in
// `suffix` (".png", ".tmx", ...).
std::vector<std::string> corpus_files(const std::string& package, const std::string& suffix);

std::string source_path(const std::string& relative); // DEPTHCULL_SOURCE_DIR/relative

} // namespace depthcull::test
