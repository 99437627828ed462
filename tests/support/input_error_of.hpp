// The message of the InputError a call throws (a test failure when it throws none).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "toolinc/core/error.hpp"

namespace toolinc::testing {

template <class F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

}  // namespace toolinc::testing
