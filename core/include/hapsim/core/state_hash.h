// StateHasher: 64-bit FNV-1a over the exact bytes of the values added, in
// the order added — the one byte hash the core uses for determinism checks
// (same inputs, same hash on every run, thread count and machine): equal
// hashes <=> (almost surely) bit-identical states, so -0.0 and 0.0, or two
// NaN payloads, hash differently.
//
//   StateHasher h;
//   h.Add(state.t_s).Add(state.x_m).Add(contact_flag);
//   std::uint64_t hash = h.Value();
//
// Only values whose bytes are all meaningful may be added: arithmetic types,
// enums and dense Eigen objects (no padding). A struct is hashed field by
// field, never as raw bytes. Never allocates; cost O(bytes), ~1 ns per byte.
#pragma once
#include <cstddef>
#include <cstdint>
#include <ranges>
#include <type_traits>

#include <Eigen/Core>

namespace hapsim::core {

class StateHasher {
 public:
  static constexpr std::uint64_t kOffsetBasis = 14695981039346656037ull;
  static constexpr std::uint64_t kPrime = 1099511628211ull;

  StateHasher& AddBytes(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) {
      hash_ ^= p[k];
      hash_ *= kPrime;
    }
    return *this;
  }

  template <typename T>
    requires(std::is_arithmetic_v<T> || std::is_enum_v<T>)
  StateHasher& Add(T value) {
    return AddBytes(&value, sizeof value);
  }

  // Dense Eigen matrix or vector: its coefficients in storage order (the
  // shape is not hashed: add it yourself where it can vary).
  template <typename Derived>
  StateHasher& Add(const Eigen::PlainObjectBase<Derived>& m) {
    using Scalar = typename Derived::Scalar;
    static_assert(std::is_arithmetic_v<Scalar>);
    return AddBytes(m.data(), sizeof(Scalar) * static_cast<std::size_t>(m.size()));
  }

  // Contiguous arithmetic values (std::vector, std::array, std::span); the
  // length is not hashed either.
  template <std::ranges::contiguous_range Range>
    requires(std::is_arithmetic_v<std::ranges::range_value_t<Range>> &&
             !std::is_base_of_v<Eigen::EigenBase<Range>, Range>)
  StateHasher& Add(const Range& values) {
    return AddBytes(std::ranges::data(values), sizeof(std::ranges::range_value_t<Range>) * std::ranges::size(values));
  }

  std::uint64_t Value() const { return hash_; }

 private:
  std::uint64_t hash_ = kOffsetBasis;
};

}  // namespace hapsim::core
