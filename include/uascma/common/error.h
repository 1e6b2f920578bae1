#pragma once
// The three tiers of errors (CONTRIBUTING.md):
//  1. Bad input from a caller or a file: throw InputError. Its message is one line that names the
//     source (a file, or "--option" on the command line), the field, and what was expected. The CLI
//     turns it into exit code 2.
//  2. A broken invariant inside uascma: UASCMA_CHECK, always on, aborts with file:line.
//  3. Costly checks: UASCMA_DCHECK, debug builds only.
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace uascma {

class InputError : public std::runtime_error {
 public:
  // "source: field: expected …" e.g. InputError("weights.yaml", "actions.NoOp", "a number, got 'abc'").
  InputError(const std::string& source, const std::string& field, const std::string& expected)
      : std::runtime_error(source + ": " + field + ": " + expected) {}
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

[[noreturn]] inline void CheckFailed(const char* condition, const char* message, const char* file, int line) {
  std::fprintf(stderr, "uascma: internal invariant failed at %s:%d: %s (%s)\n", file, line, message, condition);
  std::abort();
}

}  // namespace uascma

#define UASCMA_CHECK(condition, message) \
  ((condition) ? (void)0 : ::uascma::CheckFailed(#condition, message, __FILE__, __LINE__))

#ifdef NDEBUG
#define UASCMA_DCHECK(condition, message) ((void)0)
#else
#define UASCMA_DCHECK(condition, message) UASCMA_CHECK(condition, message)
#endif
