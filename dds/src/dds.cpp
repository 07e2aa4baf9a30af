#include "hapsim/dds/dds.h"

#include <algorithm>
#include <cstdlib>
#include <mutex>

#include "hapsim/dds/dds_default_config.h"
#include "hapsim/dds/log_limit.h"

namespace hapsim::dds {

Error::Error(const std::string& what, dds_return_t code)
    : std::runtime_error(what + ": " + dds_strretcode(code)) {}

namespace {

// The built-in XML without its "<?xml ...?>" declaration: Cyclone takes XML
// fragments in its config string, starting at the root element.
std::string BuiltInConfig() {
  std::string xml = kDefaultDdsConfigXml;
  const auto root = xml.find("<CycloneDDS");
  return root == std::string::npos ? xml : xml.substr(root);
}

}  // namespace

Participant::Participant(const Options& options) {
  LimitDdsLogRate();
  std::string config;
  if (!options.config_file.empty()) {
    config = "file://" + options.config_file;
    config_origin_ = "file " + options.config_file;
  } else if (const char* uri = std::getenv("CYCLONEDDS_URI"); uri && *uri) {
    config_origin_ = std::string("CYCLONEDDS_URI=") + uri;
  } else {
    config = BuiltInConfig();
    config_origin_ = "built-in loopback (deploy/cyclonedds-loopback.xml)";
  }
  if (!config.empty()) {
    const dds_entity_t domain = dds_create_domain(options.domain_id, config.c_str());
    if (domain < 0 && domain != DDS_RETCODE_PRECONDITION_NOT_MET) {
      throw Error("cannot create DDS domain " + std::to_string(options.domain_id) + " from " +
                         config_origin_,
                     domain);
    }
    // PRECONDITION_NOT_MET: this process already created the domain; share it.
    if (domain > 0) domain_ = domain;
  }
  participant_ = dds_create_participant(options.domain_id, nullptr, nullptr);
  if (participant_ < 0) {
    const auto code = participant_;
    participant_ = 0;
    if (domain_ > 0) dds_delete(domain_);
    throw Error("cannot create DDS participant (domain " + std::to_string(options.domain_id) +
                       ", config " + config_origin_ + ")",
                   code);
  }
}

Participant::~Participant() {
  if (participant_ > 0) dds_delete(participant_);
  if (domain_ > 0) dds_delete(domain_);
}

void Entity::Reset() {
  if (handle_ > 0) dds_delete(handle_);
  handle_ = 0;
}

dds_entity_t CreateTopicOrThrow(const Participant& p, const dds_topic_descriptor_t* desc,
                                const char* name) {
  const dds_entity_t topic = dds_create_topic(p.handle(), desc, name, nullptr, nullptr);
  if (topic < 0) throw Error(std::string("cannot create DDS topic ") + name, topic);
  return topic;
}

namespace {
dds_qos_t* HapsimQos() {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
  dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  return qos;
}
}  // namespace

namespace {

// A publisher (for_writer) or subscriber in one partition, or none.
Entity PartitionParent(const Participant& p, const std::string& partition, bool for_writer) {
  if (partition.empty()) return Entity();
  dds_qos_t* qos = dds_create_qos();
  dds_qset_partition1(qos, partition.c_str());
  const dds_entity_t e = for_writer ? dds_create_publisher(p.handle(), qos, nullptr)
                                    : dds_create_subscriber(p.handle(), qos, nullptr);
  dds_delete_qos(qos);
  if (e < 0) throw Error("cannot create DDS " + std::string(for_writer ? "publisher" : "subscriber") +
                                " for partition " + partition, e);
  return Entity(e);
}

}  // namespace

Endpoint CreateWriterOrThrow(const Participant& p, dds_entity_t topic, const std::string& partition) {
  Endpoint out;
  out.parent = PartitionParent(p, partition, /*for_writer=*/true);
  dds_qos_t* qos = HapsimQos();
  const dds_entity_t w = dds_create_writer(partition.empty() ? p.handle() : out.parent.handle(), topic, qos, nullptr);
  dds_delete_qos(qos);
  if (w < 0) throw Error("cannot create DDS writer", w);
  out.endpoint = Entity(w);
  return out;
}

Endpoint CreateReaderOrThrow(const Participant& p, dds_entity_t topic, const std::string& partition) {
  Endpoint out;
  out.parent = PartitionParent(p, partition, /*for_writer=*/false);
  dds_qos_t* qos = HapsimQos();
  const dds_entity_t r = dds_create_reader(partition.empty() ? p.handle() : out.parent.handle(), topic, qos, nullptr);
  dds_delete_qos(qos);
  if (r < 0) throw Error("cannot create DDS reader", r);
  out.endpoint = Entity(r);
  return out;
}

WaitSet::WaitSet(const Participant& p) {
  const dds_entity_t ws = dds_create_waitset(p.handle());
  if (ws < 0) throw Error("cannot create DDS waitset", ws);
  waitset_ = Entity(ws);
  const dds_entity_t gc = dds_create_guardcondition(p.handle());
  if (gc < 0) throw Error("cannot create DDS guard condition", gc);
  guard_ = Entity(gc);
  const dds_return_t rc = dds_waitset_attach(ws, gc, kGuardTag);
  if (rc < 0) throw Error("cannot attach guard condition", rc);
}

Entity WaitSet::AttachReader(dds_entity_t reader, dds_attach_t tag) {
  const dds_entity_t rc = dds_create_readcondition(reader, DDS_ANY_STATE);
  if (rc < 0) throw Error("cannot create read condition", rc);
  Entity condition(rc);
  const dds_return_t r = dds_waitset_attach(waitset_.handle(), rc, tag);
  if (r < 0) throw Error("cannot attach read condition", r);
  return condition;
}

std::size_t WaitSet::Wait(std::int64_t timeout_ns, std::span<dds_attach_t> tags) {
  const dds_return_t n = dds_waitset_wait(waitset_.handle(), tags.data(), tags.size(), timeout_ns);
  bool was = false;
  dds_take_guardcondition(guard_.handle(), &was);
  if (n <= 0) return 0;
  return std::min(static_cast<std::size_t>(n), tags.size());
}

void WaitSet::Wake() { dds_set_guardcondition(guard_.handle(), true); }

}  // namespace hapsim::dds
