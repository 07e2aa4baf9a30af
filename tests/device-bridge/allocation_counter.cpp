// This binary's counting operator new: the one hapsim-core-tests uses
// (tests/core/allocation_counter.h explains why there is only one per binary).
#include "core/allocation_counter.cpp"  // NOLINT(bugprone-suspicious-include)
