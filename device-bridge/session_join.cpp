#include "session_join.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <optional>
#include <stdexcept>

#include "hapsim/v1/session.grpc.pb.h"
#include "hapsim/viewer/connection.h"
#include "hapsim/viewer/session_client.h"
#include "hapsim/viewer/session_locator.h"

namespace hapsim::bridge {

namespace {

constexpr double kCallTimeoutS = 10.0;  // also how long a server not up yet is waited for

// JoinSession at the server that hosts the session.
hapsim::v1::JoinSessionResponse Join(const viewer::Connection& at, const std::string& session) {
  auto stub = hapsim::v1::SessionService::NewStub(viewer::MakeChannel(at));
  grpc::ClientContext context;
  viewer::AddToken(&context, at.token);
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(static_cast<int>(kCallTimeoutS)));
  hapsim::v1::SessionRef ref;
  ref.set_session_id(session);
  hapsim::v1::JoinSessionResponse joined;
  const grpc::Status status = stub->JoinSession(&context, ref, &joined);
  if (!status.ok()) {
    throw std::runtime_error("cannot join session '" + session + "' at " + at.address + ": " +
                             viewer::DescribeStatus(status));
  }
  return joined;
}

}  // namespace

struct SessionJoiner::Flags {
  viewer::Connection connection;
  viewer::ConnectionFlags connection_flags;
};

SessionJoiner::SessionJoiner() : flags_(std::make_unique<Flags>()) { flags_->connection.address.clear(); }
SessionJoiner::~SessionJoiner() = default;

void SessionJoiner::AddFlags(common::Flags* flags) {
  flags->Add("join", &flags_->connection.address,
             "before streaming, find each session's server through this one (HOST:PORT of any server of the\n"
             "site) and join it there: its token is checked and its DDS domain used. Empty: DDS only");
  viewer::AddConnectionFlags(flags, &flags_->connection, &flags_->connection_flags);
}

bool SessionJoiner::enabled() const { return !flags_->connection.address.empty(); }

std::uint32_t SessionJoiner::JoinAll(const std::vector<std::string>& sessions) {
  std::string error;
  if (!viewer::FinishConnectionFlags(flags_->connection_flags, &flags_->connection, &error)) {
    throw std::runtime_error(error);
  }
  std::optional<std::uint32_t> domain;
  for (const auto& session : sessions) {
    const auto location = viewer::LocateSession(flags_->connection, session, kCallTimeoutS, true);
    if (viewer::LocateStopsTheClient(location)) {
      throw std::runtime_error("cannot locate session '" + session + "': " + viewer::DescribeStatus(location.status));
    }
    const auto joined = Join(location.connection, session);
    spdlog::info("{}: joined, DDS domain {}, partition {}",
                 location.status.ok() ? viewer::DescribeLocation(location) : "session " + session, joined.dds_domain(),
                 joined.dds_partition());
    if (domain && *domain != joined.dds_domain()) {
      throw std::runtime_error("the sessions are on different DDS domains (" + std::to_string(*domain) + " and " +
                               std::to_string(joined.dds_domain()) + "): one bridge process joins one domain");
    }
    domain = joined.dds_domain();
  }
  return domain.value_or(0);
}

}  // namespace hapsim::bridge
