#include "hapsim/dds/publication_watch.h"

#include <array>
#include <cstring>

namespace hapsim::dds {

PublicationWatch::PublicationWatch(const Participant& participant) {
  const dds_return_t got = dds_get_guid(participant.handle(), &own_guid_);
  if (got != DDS_RETCODE_OK) throw Error("cannot read the DDS participant's GUID", got);
  const dds_entity_t reader = dds_create_reader(participant.handle(), DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, nullptr);
  if (reader < 0) throw Error("cannot create a reader of DCPSPublication", reader);
  reader_ = Entity(reader);
}

std::size_t PublicationWatch::Take(const std::function<void(const RemotePublication&)>& on_change) {
  constexpr std::size_t kBatch = 16;
  std::size_t reported = 0;
  for (;;) {
    // Loaned samples: the built-in type holds pointers (names, QoS).
    std::array<void*, kBatch> samples{};
    std::array<dds_sample_info_t, kBatch> infos{};
    const dds_return_t n = dds_take(reader_.handle(), samples.data(), infos.data(), kBatch, kBatch);
    if (n <= 0) return reported;
    for (dds_return_t i = 0; i < n; ++i) {
      const auto* endpoint = static_cast<const dds_builtintopic_endpoint_t*>(samples[i]);
      RemotePublication pub;
      pub.handle = infos[i].instance_handle;
      pub.alive = infos[i].valid_data && infos[i].instance_state == DDS_IST_ALIVE;
      if (infos[i].valid_data) {
        if (std::memcmp(endpoint->participant_key.v, own_guid_.v, sizeof own_guid_.v) == 0) continue;
        std::memcpy(&pub.participant_prefix, endpoint->participant_key.v, sizeof pub.participant_prefix);
        if (pub.alive) {
          pub.topic = endpoint->topic_name ? endpoint->topic_name : "";
          std::uint32_t count = 0;
          char** names = nullptr;
          if (endpoint->qos && dds_qget_partition(endpoint->qos, &count, &names)) {
            for (std::uint32_t k = 0; k < count; ++k) {
              pub.partitions.emplace_back(names[k]);
              dds_free(names[k]);
            }
            dds_free(names);
          }
        }
      }
      on_change(pub);
      ++reported;
    }
    dds_return_loan(reader_.handle(), samples.data(), n);
    if (static_cast<std::size_t>(n) < kBatch) return reported;
  }
}

}  // namespace hapsim::dds
