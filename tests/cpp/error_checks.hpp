#pragma once
// Shared checks of the library's bad-input errors in satgnc gtests: std::invalid_argument with a message
// that names the argument (docs/architecture.md §3).
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace satgnc::testing {

/// The message of the std::invalid_argument that fn() throws, or `none` when it throws nothing.
template <class Fn>
std::string message_of(Fn&& fn, const std::string& none = "no exception") {
  try {
    fn();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return none;
}

/// Adds a failure unless f() throws std::invalid_argument with a message containing text.
template <class F>
void expect_error(F&& f, const std::string& text) {
  try {
    f();
    ADD_FAILURE() << "no exception, expected one containing: " << text;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

}  // namespace satgnc::testing
