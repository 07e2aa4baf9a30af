// The three error tiers of hapsim::core (after Drake's drake_assert.h):
//  1. bad user input (parameters, meshes) throws a typed error at the edge,
//     in a ...Def -> Build or a Parse function — never inside a step;
//  2. a numerical blow-up inside a step is detected, counted and recovered
//     by the scene (a reset), never a crash;
//  3. a programming error (an index a caller got wrong, a broken invariant)
//     is stopped by these macros: the process aborts with the condition,
//     file, line and message on stderr.
//
//   HAPSIM_DEMAND(cond, msg)  always checked: one predictable branch; for
//                             cheap checks whose failure would corrupt memory.
//   HAPSIM_ASSERT(cond, msg)  checked in debug builds only (NDEBUG unset);
//                             free in release, for checks on hot paths.
//
// Both are no-throw: a step that uses them stays noexcept in spirit.
#pragma once

namespace hapsim::core {

// Writes "hapsim: <file>:<line>: <kind> failed: <condition>: <message>" to
// stderr and aborts. The one place in the core that writes anything.
[[noreturn]] void AbortOnFailedCheck(const char* kind, const char* condition, const char* file, int line,
                                     const char* message) noexcept;

}  // namespace hapsim::core

#define HAPSIM_DEMAND(condition, message)                                                          \
  do {                                                                                             \
    if (!(condition)) [[unlikely]]                                                                 \
      ::hapsim::core::AbortOnFailedCheck("HAPSIM_DEMAND", #condition, __FILE__, __LINE__, message); \
  } while (false)

#ifdef NDEBUG
// Not evaluated, but still compiled, so it cannot rot.
#define HAPSIM_ASSERT(condition, message) \
  do {                                    \
    if (false && (condition)) {           \
      (void)(message);                    \
    }                                     \
  } while (false)
#else
#define HAPSIM_ASSERT(condition, message)                                                          \
  do {                                                                                             \
    if (!(condition)) [[unlikely]]                                                                 \
      ::hapsim::core::AbortOnFailedCheck("HAPSIM_ASSERT", #condition, __FILE__, __LINE__, message); \
  } while (false)
#endif
