#pragma once
// The Error a call throws, for tests that check a refusal's kind and field: a test failure (and kInternal) when the
// call throws none. One helper for the test files that each wrote it.
#include <gtest/gtest.h>

#include <functional>

#include "schema/error.h"

namespace anchordb::testing {

inline Error ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return Error(ErrorCode::kInternal, "no error");
}

inline ErrorCode CodeOf(const std::function<void()>& f) { return ErrorOf(f).code(); }

}  // namespace anchordb::testing
