// PLEAT_ASSERT: internal invariants. A violation is a bug: it throws pleat::InvariantError with file:line.
// Checked in Debug builds, and in optimized ones built with PLEAT_CHECK_INVARIANTS (a CMake option, on by
// default: the Release build and the tests check); compiled away only in an optimized build without it.
// Cost: the condition's, where checked. Thread safety: as the condition's.
#pragma once

#include <stdexcept>
#include <string>

namespace pleat {
class InvariantError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};
}  // namespace pleat

/// 1 where PLEAT_ASSERT checks (for a loop that exists only to assert), else 0.
#if !defined(NDEBUG) || defined(PLEAT_CHECK_INVARIANTS)
#define PLEAT_ASSERTS_ON 1
#else
#define PLEAT_ASSERTS_ON 0
#endif

#if PLEAT_ASSERTS_ON
#define PLEAT_ASSERT(cond, msg)                                                                             \
  do {                                                                                                      \
    if (!(cond))                                                                                            \
      throw ::pleat::InvariantError(std::string(__FILE__) + ":" + std::to_string(__LINE__) + ": " + #cond + \
                                    ": " + (msg));                                                          \
  } while (false)
#else
#define PLEAT_ASSERT(cond, msg) \
  do {                          \
  } while (false)
#endif
