// Small RAII wrappers over the Cyclone DDS C API (no C++ binding is packaged
// for Debian 12). One participant per process; topics with hapsim's QoS
// (best effort, keep-last 1, volatile); a waitset for the I/O threads.
//
// Configuration, in order: --dds-config FILE if given; else the environment
// variable CYCLONEDDS_URI if set; else the built-in loopback configuration
// (deploy/cyclonedds-loopback.xml, embedded at build time) — so by default
// DDS never leaves 127.0.0.1.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include <dds/dds.h>

#include "hapsim/dds/partition.h"  // SessionPartition: the partition an endpoint joins

namespace hapsim::dds {

class Error : public std::runtime_error {
 public:
  Error(const std::string& what, dds_return_t code);
};

struct Options {
  std::uint32_t domain_id = 0;
  std::string config_file;  // empty: CYCLONEDDS_URI if set, else built-in loopback
};

class Participant {
 public:
  explicit Participant(const Options& options);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  dds_entity_t handle() const { return participant_; }
  // Human-readable origin of the configuration in use (for logs).
  const std::string& config_origin() const { return config_origin_; }

 private:
  dds_entity_t domain_ = 0;  // non-zero when this object created the domain
  dds_entity_t participant_ = 0;
  std::string config_origin_;
};

// Owns any DDS entity handle (topic, reader, writer, waitset, condition).
class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t handle) : handle_(handle) {}
  ~Entity() { Reset(); }
  Entity(Entity&& other) noexcept : handle_(other.handle_) { other.handle_ = 0; }
  Entity& operator=(Entity&& other) noexcept {
    if (this != &other) {
      Reset();
      handle_ = other.handle_;
      other.handle_ = 0;
    }
    return *this;
  }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  dds_entity_t handle() const { return handle_; }
  void Reset();

 private:
  dds_entity_t handle_ = 0;
};

dds_entity_t CreateTopicOrThrow(const Participant& p, const dds_topic_descriptor_t* desc,
                                const char* name);

// A publisher or subscriber (parent) and the writer or reader on it. With an
// empty partition the parent is the participant's default one.
struct Endpoint {
  Entity parent;    // publisher/subscriber created for the partition (or none)
  Entity endpoint;  // writer/reader
};
// Best effort, keep-last 1 per instance, volatile; in `partition` if not empty.
Endpoint CreateWriterOrThrow(const Participant& p, dds_entity_t topic, const std::string& partition = {});
Endpoint CreateReaderOrThrow(const Participant& p, dds_entity_t topic, const std::string& partition = {});

template <class T>
class Writer {
 public:
  Writer(const Participant& p, const dds_topic_descriptor_t* desc, const char* topic_name,
            const std::string& partition = {})
      : topic_(CreateTopicOrThrow(p, desc, topic_name)), writer_(CreateWriterOrThrow(p, topic_.handle(), partition)) {}
  // Thread-safe. Returns false when DDS refused the sample (logged by the caller).
  bool Write(const T& sample) { return dds_write(writer_.endpoint.handle(), &sample) == DDS_RETCODE_OK; }
  dds_entity_t handle() const { return writer_.endpoint.handle(); }

 private:
  Entity topic_;
  Endpoint writer_;
};

template <class T>
class Reader {
 public:
  Reader(const Participant& p, const dds_topic_descriptor_t* desc, const char* topic_name,
            const std::string& partition = {})
      : topic_(CreateTopicOrThrow(p, desc, topic_name)), reader_(CreateReaderOrThrow(p, topic_.handle(), partition)) {}
  // Takes up to out.size() valid samples into out (no allocation: T is
  // fixed-size); returns how many.
  std::size_t Take(std::span<T> out) {
    constexpr std::size_t kMax = 64;
    void* buffers[kMax];
    dds_sample_info_t infos[kMax];
    const std::size_t n = out.size() < kMax ? out.size() : kMax;
    for (std::size_t i = 0; i < n; ++i) buffers[i] = &out[i];
    const dds_return_t got = dds_take(handle(), buffers, infos, n, static_cast<std::uint32_t>(n));
    if (got <= 0) return 0;
    // Compact away invalid samples (disposals carry no data).
    std::size_t valid = 0;
    for (std::size_t i = 0; i < static_cast<std::size_t>(got); ++i) {
      if (!infos[i].valid_data) continue;
      if (valid != i) out[valid] = out[i];
      ++valid;
    }
    return valid;
  }
  dds_entity_t handle() const { return reader_.endpoint.handle(); }

 private:
  Entity topic_;
  Endpoint reader_;
};

// A waitset an I/O thread sleeps on: wakes when a reader has data, when
// Wake() is called (guard condition) or on timeout.
class WaitSet {
 public:
  explicit WaitSet(const Participant& p);
  // Attaches a reader: the returned read condition is attached with `tag`
  // (reported by Wait; not kGuardTag) and detached when the caller
  // destroys it. Thread-safe against a concurrent wait.
  Entity AttachReader(dds_entity_t reader, dds_attach_t tag);
  // Thread-safe; cheap. Used by real-time threads to say "new data to send".
  void Wake();
  // Returns after an event or timeout_ns and resets the guard condition.
  // Fills `tags` with the tags of the triggered conditions (kGuardTag for
  // the guard condition); returns how many (at most tags.size()).
  std::size_t Wait(std::int64_t timeout_ns, std::span<dds_attach_t> tags);
  static constexpr dds_attach_t kGuardTag = 0;

 private:
  Entity waitset_;
  Entity guard_;
};

}  // namespace hapsim::dds
