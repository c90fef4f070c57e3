// Helpers shared by the scene reader tests: a small valid scene, and errors checked against the
// line marked "# <-" in the text.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/scene/scene_reader.h"

namespace polydem::scene::scene_test {

// 1-based line of the n-th line of `text` containing `needle`.
inline int lineContaining(const std::string& text, const std::string& needle, int n = 0) {
  int line = 1;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    if (text.substr(start, end - start).find(needle) != std::string::npos && n-- == 0) return line;
    start = end + 1;
    ++line;
  }
  ADD_FAILURE() << "'" << needle << "' not in the text";
  return -1;
}

inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The error parsing `text` raises; the test fails if there is none.
inline InputError errorOf(const std::string& text) {
  try {
    parseScene(text, "test.toml");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return InputError("", -1, "");
}

// Expects an error at the line marked "# <-" whose message contains every fragment.
inline void expectError(const std::string& text, const std::vector<std::string>& fragments) {
  const InputError e = errorOf(text);
  EXPECT_EQ(e.file(), "test.toml");
  EXPECT_EQ(e.line(), lineContaining(text, "# <-")) << e.what();
  for (const std::string& f : fragments) {
    EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
        << "'" << f << "' not in: " << e.what();
  }
}

inline const std::string kBase = R"([scene]
id = "T-BASE"

[simulation]
kernel = "gjk-epa-ipm"
dt = 1e-4
steps = 10

[[material]]
name = "rock"
density = 2500
kn = 1e9

[[shape]]
name = "cube"
type = "cube"
edge = 1

[[particle]]
label = "a"
shape = "cube"
material = "rock"
)";

}  // namespace polydem::scene::scene_test
