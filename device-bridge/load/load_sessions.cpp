#include "load_sessions.h"

namespace hapsim::bridge {

std::string CheckSceneParams(const std::string& params) {
  v1::CreateSessionRequest scratch;
  for (const auto& kv : SplitCommaList(params)) {
    if (!viewer::AddSceneParam(kv, scratch.mutable_params())) return "--params wants KEY=NUMBER,..., got '" + kv + "'";
  }
  return "";
}

std::string CreateSessions(viewer::SessionClient& client, const std::vector<LoadDevicePlan>& plan,
                           const SessionSpec& spec, std::vector<std::string>* created) {
  v1::CreateSessionRequest request;
  request.set_scene(spec.scene);
  request.set_owner(spec.owner);
  for (const auto& kv : SplitCommaList(spec.params)) {
    if (!viewer::AddSceneParam(kv, request.mutable_params())) return "--params wants KEY=NUMBER,..., got '" + kv + "'";
  }
  for (const auto& device : plan) {
    request.set_session_id(device.session);
    v1::SessionInfo info;
    const grpc::Status status = client.Create(request, &info);
    if (!status.ok()) {
      std::string error = "session '" + device.session + "' (scene " + spec.scene + "): " + viewer::DescribeStatus(status);
      const std::string cleanup = CloseSessions(client, *created);
      if (!cleanup.empty()) error += "\nwhile closing the sessions created before it: " + cleanup;
      created->clear();
      return error;
    }
    created->push_back(device.session);
  }
  return "";
}

std::string CloseSessions(viewer::SessionClient& client, const std::vector<std::string>& ids) {
  std::string errors;
  for (const auto& id : ids) {
    const grpc::Status status = client.Close(id);
    if (status.ok()) continue;
    if (!errors.empty()) errors += '\n';
    errors += "session '" + id + "': " + viewer::DescribeStatus(status);
  }
  return errors;
}

std::vector<ServerSessionStats> FetchServerStats(viewer::SessionClient& client, const std::vector<LoadDevicePlan>& plan) {
  std::vector<ServerSessionStats> stats;
  for (const auto& device : plan) {
    ServerSessionStats s;
    s.session_id = device.session;
    v1::SessionInfo i;
    const grpc::Status status = client.Get(device.session, &i);
    if (!status.ok()) {
      s.error = viewer::DescribeStatus(status);
    } else {
      s.ticks = i.ticks();
      s.late_ticks = i.late_ticks();
      s.device_clocked_ticks = i.device_clocked_ticks();
      s.poses_received = i.poses_received();
      s.poses_rejected = i.poses_rejected();
      s.poses_from_other_devices = i.poses_from_other_devices();
      s.force_models_sent = i.force_models_sent();
      s.owning_device_id = i.owning_device_id();
      s.device_streaming = i.device_streaming();
      s.max_tick_lateness_s = i.max_tick_lateness_s();
    }
    stats.push_back(std::move(s));
  }
  return stats;
}

}  // namespace hapsim::bridge
