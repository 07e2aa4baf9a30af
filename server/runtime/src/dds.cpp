#include "hapsim/runtime/dds.h"

#include <cstdlib>
#include <mutex>

#include "hapsim/runtime/dds_default_config.h"

namespace hapsim::runtime {

DdsError::DdsError(const std::string& what, dds_return_t code)
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

DdsParticipant::DdsParticipant(const DdsOptions& options) {
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
      throw DdsError("cannot create DDS domain " + std::to_string(options.domain_id) + " from " +
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
    throw DdsError("cannot create DDS participant (domain " + std::to_string(options.domain_id) +
                       ", config " + config_origin_ + ")",
                   code);
  }
}

DdsParticipant::~DdsParticipant() {
  if (participant_ > 0) dds_delete(participant_);
  if (domain_ > 0) dds_delete(domain_);
}

void DdsEntity::Reset() {
  if (handle_ > 0) dds_delete(handle_);
  handle_ = 0;
}

dds_entity_t CreateTopicOrThrow(const DdsParticipant& p, const dds_topic_descriptor_t* desc,
                                const char* name) {
  const dds_entity_t topic = dds_create_topic(p.handle(), desc, name, nullptr, nullptr);
  if (topic < 0) throw DdsError(std::string("cannot create DDS topic ") + name, topic);
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

dds_entity_t CreateWriterOrThrow(const DdsParticipant& p, dds_entity_t topic) {
  dds_qos_t* qos = HapsimQos();
  const dds_entity_t w = dds_create_writer(p.handle(), topic, qos, nullptr);
  dds_delete_qos(qos);
  if (w < 0) throw DdsError("cannot create DDS writer", w);
  return w;
}

dds_entity_t CreateReaderOrThrow(const DdsParticipant& p, dds_entity_t topic) {
  dds_qos_t* qos = HapsimQos();
  const dds_entity_t r = dds_create_reader(p.handle(), topic, qos, nullptr);
  dds_delete_qos(qos);
  if (r < 0) throw DdsError("cannot create DDS reader", r);
  return r;
}

DdsWaitSet::DdsWaitSet(const DdsParticipant& p) {
  const dds_entity_t ws = dds_create_waitset(p.handle());
  if (ws < 0) throw DdsError("cannot create DDS waitset", ws);
  waitset_ = DdsEntity(ws);
  const dds_entity_t gc = dds_create_guardcondition(p.handle());
  if (gc < 0) throw DdsError("cannot create DDS guard condition", gc);
  guard_ = DdsEntity(gc);
  const dds_return_t rc = dds_waitset_attach(ws, gc, 0);
  if (rc < 0) throw DdsError("cannot attach guard condition", rc);
}

void DdsWaitSet::AttachReader(dds_entity_t reader) {
  if (n_read_conditions_ == 4) throw std::logic_error("DdsWaitSet: at most 4 readers");
  const dds_entity_t rc = dds_create_readcondition(reader, DDS_ANY_STATE);
  if (rc < 0) throw DdsError("cannot create read condition", rc);
  read_conditions_[n_read_conditions_++] = DdsEntity(rc);
  const dds_return_t r = dds_waitset_attach(waitset_.handle(), rc, reader);
  if (r < 0) throw DdsError("cannot attach read condition", r);
}

void DdsWaitSet::Wake() { dds_set_guardcondition(guard_.handle(), true); }

void DdsWaitSet::Wait(std::int64_t timeout_ns) {
  dds_attach_t triggered[8];
  dds_waitset_wait(waitset_.handle(), triggered, 8, timeout_ns);
  bool was = false;
  dds_take_guardcondition(guard_.handle(), &was);
}

}  // namespace hapsim::runtime
