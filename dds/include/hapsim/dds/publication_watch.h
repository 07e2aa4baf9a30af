// Discovery of other participants' writers through Cyclone's built-in
// DCPSPublication topic: which topics they publish, in which partitions.
// The server uses it to notice a second server publishing force models in
// one of its sessions' partitions (a bridge there would get both servers'
// models). Only discovery data flows; no sample of the watched topics.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "hapsim/dds/dds.h"

namespace hapsim::dds {

// A writer of another participant, as discovery last described it.
struct RemotePublication {
  dds_instance_handle_t handle = 0;  // this publication's instance (stable while it lives)
  bool alive = true;                 // false: the writer or its participant is gone (topic/partitions empty)
  std::string topic;
  std::vector<std::string> partitions;
  std::uint64_t participant_prefix = 0;  // first 8 bytes of the participant's GUID (for logs)
};

class PublicationWatch {
 public:
  explicit PublicationWatch(const Participant& participant);

  // The reader to attach to an I/O thread's waitset.
  dds_entity_t handle() const { return reader_.handle(); }
  // Takes every waiting discovery sample and calls on_change for each that
  // describes another participant's writer. Returns how many it reported.
  std::size_t Take(const std::function<void(const RemotePublication&)>& on_change);

 private:
  dds_guid_t own_guid_{};
  Entity reader_;
};

}  // namespace hapsim::dds
