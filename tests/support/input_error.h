#pragma once
// The message of the uascma::InputError that `f` throws, or "" when it throws none (shared by the tests
// that check that bad input is refused with a message naming the field).
#include <functional>
#include <string>

#include "uascma/common/error.h"

namespace uascma::testing_support {

inline std::string InputErrorMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace uascma::testing_support
