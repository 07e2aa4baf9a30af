// Eigen's large products and decompositions the same on every CPU.
//
// Eigen splits a dynamic-size matrix product into blocks sized from the
// CPU's caches, which it reads with CPUID the first time it needs them. Two
// CPUs with another L1 size (32 KiB on one AMD EPYC host, 48 KiB on the
// next) split the same sums at other places, and the last bits differ: the
// acupuncture scene's spherical-harmonic fit (an SVD of a 1 000 x 81 design
// matrix) then ended in another golden hash. Pinning the sizes Eigen blocks
// with to fixed values makes those products identical everywhere; only
// their speed still depends on the CPU.
#pragma once
#include <cstddef>

namespace hapsim::core {

// The cache sizes every hapsim process tells Eigen (bytes): the L1 of the
// host the current golden hashes were recorded on, and ordinary L2 / L3.
inline constexpr std::ptrdiff_t kEigenL1CacheBytes = 32 * 1024;
inline constexpr std::ptrdiff_t kEigenL2CacheBytes = 1024 * 1024;
inline constexpr std::ptrdiff_t kEigenL3CacheBytes = 32 * 1024 * 1024;

// Sets them unless Eigen already uses them. Call before any dynamic-size
// product or decomposition whose result reaches state or a score (scene
// builds, fits, scoring). Cheap after the first call (three reads); thread-
// safe once set (the first call should come before worker threads compute).
void PinEigenBlockingSizes();

}  // namespace hapsim::core
