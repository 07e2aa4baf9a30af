// The bounded log of a mesh's topology edits: every vertex or triangle added
// or removed, in order, each advancing the topology version by one. A viewer
// stream that holds version v is brought up to date by the edits [v, now);
// if the log no longer holds v (it wrapped, or the mesh was reset), the
// stream needs a keyframe instead. Capacity is fixed at construction; Push()
// never allocates (the oldest edit is overwritten).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace hapsim::core {

struct TopologyEdit {
  enum class Kind : std::uint8_t { kAddVertex = 0, kRemoveVertex = 1, kAddTriangle = 2, kRemoveTriangle = 3 };
  Kind kind = Kind::kAddVertex;
  std::uint16_t part = 0;                    // kAddTriangle: index into the part names
  std::uint32_t slot = 0;                    // the vertex or triangle slot
  std::array<std::uint32_t, 3> vertices{};   // kAddTriangle: its vertex slots (counter-clockwise from outside)
  friend bool operator==(const TopologyEdit&, const TopologyEdit&) = default;
};

class TopologyLog {
 public:
  explicit TopologyLog(std::size_t capacity = 4096) : ring_(capacity) {}

  // Appends one edit: the version advances by one.
  void Push(const TopologyEdit& edit);
  // Forget every edit and advance the version by one: whoever held an older
  // version must start over from a keyframe (a scene reset).
  void Restart();

  // Edits ever pushed plus restarts: the version of the current topology.
  std::uint64_t Version() const { return version_; }
  // The oldest version the log can bring up to date (edits [Oldest(), Version())).
  std::uint64_t Oldest() const { return oldest_; }
  bool Covers(std::uint64_t from_version) const { return from_version >= oldest_ && from_version <= version_; }
  // The edit that moved the topology from `version` to version + 1
  // (Covers(version) and version < Version()).
  const TopologyEdit& At(std::uint64_t version) const { return ring_[version % ring_.size()]; }
  std::size_t Capacity() const { return ring_.size(); }

 private:
  std::vector<TopologyEdit> ring_;
  std::uint64_t version_ = 0;
  std::uint64_t oldest_ = 0;
};

}  // namespace hapsim::core
