#include "row_codec.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "hapsim/store/text_codecs.h"

namespace hapsim::service::store_internal {

const TableSpec kSessionsTable = {
    "sessions",
    {"id", "scene", "params", "owner", "class_name", "run_id", "created_unix_ms", "recording_path"},
    {"id"}};

const TableSpec kTrialsTable = {"trials",
                                {"session_id",
                                 "run_id",
                                 "trial",
                                 "trainee",
                                 "scene",
                                 "class_name",
                                 "end_state",
                                 "start_sim_s",
                                 "last_sim_s",
                                 "first_contact_sim_s",
                                 "peak_force_N",
                                 "max_tip_depth_m",
                                 "peak_force_in_layer_N",
                                 "layers_pierced_mask",
                                 "punctures",
                                 "cuts",
                                 "incision_length_m",
                                 "line_deviation_max_m",
                                 "line_deviation_sum_m",
                                 "line_deviation_mean_m",
                                 "cutting_ticks",
                                 "ticks",
                                 "layer_names",
                                 "target_depth_m",
                                 "target_line_x0_m",
                                 "target_line_y0_m",
                                 "target_line_x1_m",
                                 "target_line_y1_m",
                                 "recording_path",
                                 "updated_unix_ms"},
                                {"session_id", "run_id", "trial"}};

const TableSpec kRecordingsTable = {"recordings",
                                    {"path", "session_id", "run_id", "trial", "trainee", "class_name", "scene",
                                     "started_unix_ms", "ended_unix_ms", "ticks", "bytes", "status"},
                                    {"path"}};

namespace {

std::string ColumnList(const TableSpec& table) {
  std::string out;
  for (const auto column : table.columns) {
    if (!out.empty()) out += ", ";
    out += column;
  }
  return out;
}

}  // namespace

std::string UpsertSql(const TableSpec& table) {
  std::string sql = "INSERT INTO " + std::string(table.name) + " (" + ColumnList(table) + ") VALUES (";
  for (std::size_t i = 0; i < table.columns.size(); ++i) sql += i ? ", ?" : "?";
  sql += ") ON CONFLICT (";
  for (std::size_t i = 0; i < table.key.size(); ++i) sql += (i ? ", " : "") + std::string(table.key[i]);
  sql += ") DO UPDATE SET ";
  bool first = true;
  for (const auto column : table.columns) {
    if (std::find(table.key.begin(), table.key.end(), column) != table.key.end()) continue;
    sql += (first ? "" : ", ") + std::string(column) + " = excluded." + std::string(column);
    first = false;
  }
  return sql;
}

std::string SelectSql(const TableSpec& table, std::string_view tail) {
  return "SELECT " + ColumnList(table) + " FROM " + std::string(table.name) + " " + std::string(tail);
}

void BindSession(Statement& s, const StoredSession& row) {
  Binder(s)
      .Text(row.id)
      .Text(row.scene)
      .Text(store_codec::EncodeParams(row.params))
      .Text(row.owner)
      .Text(row.class_name)
      .Text(row.run_id)
      .Int(row.created_unix_ms)
      .Text(row.recording_path);
}

StoredSession ReadSession(const Statement& s) {
  Cursor c(s);
  StoredSession row;
  row.id = c.Text();
  row.scene = c.Text();
  row.params = store_codec::DecodeParams(c.Text());
  row.owner = c.Text();
  row.class_name = c.Text();
  row.run_id = c.Text();
  row.created_unix_ms = c.Int();
  row.recording_path = c.Text();
  return row;
}

void BindTrial(Statement& s, const StoredTrial& row) {
  const TrialRecord& r = row.record;
  const TrialStats& t = r.stats;
  const bool has_line = r.targets.has_line();  // no line: all four NULL
  const auto line = [&](int i) { return has_line ? r.targets.line_m[i] : std::numeric_limits<double>::quiet_NaN(); };
  Binder(s)
      .Text(r.session_id)
      .Text(row.run_id)
      .Uint(t.trial)
      .Text(r.trainee)
      .Text(r.scene)
      .Text(row.class_name)
      .Text(r.end)
      .Real(t.start_sim_s)
      .Real(t.last_sim_s)
      .Real(t.first_contact_sim_s)
      .Real(t.peak_force_N)
      .Real(t.max_tip_depth_m)
      .Text(store_codec::EncodeDoubles(t.peak_force_in_layer_N))
      .Uint(t.layers_pierced_mask)
      .Uint(t.punctures)
      .Uint(t.cuts)
      .Real(t.incision_length_m)
      .Real(t.line_deviation_max_m)
      .Real(t.line_deviation_sum_m)
      .Real(t.line_deviation_mean_m())
      .Uint(t.cutting_ticks)
      .Uint(t.ticks)
      .Text(store_codec::JoinNames(r.layer_names))
      .Real(r.targets.depth_m)
      .Real(line(0))
      .Real(line(1))
      .Real(line(2))
      .Real(line(3))
      .Text(row.recording_path)
      .Int(row.updated_unix_ms);
}

StoredTrial ReadTrial(const Statement& s) {
  Cursor c(s);
  StoredTrial row;
  TrialRecord& r = row.record;
  TrialStats& t = r.stats;
  r.session_id = c.Text();
  row.run_id = c.Text();
  t.trial = c.Uint();
  r.trainee = c.Text();
  r.scene = c.Text();
  row.class_name = c.Text();
  r.end = c.Text();
  t.start_sim_s = c.Real();
  t.last_sim_s = c.Real();
  t.first_contact_sim_s = c.Real();
  t.peak_force_N = c.Real();
  t.max_tip_depth_m = c.Real();
  const std::vector<double> by_layer = store_codec::DecodeDoubles(c.Text());
  std::copy_n(by_layer.begin(), std::min(by_layer.size(), t.peak_force_in_layer_N.size()),
              t.peak_force_in_layer_N.begin());
  t.layers_pierced_mask = static_cast<std::uint32_t>(c.Int());
  t.punctures = static_cast<std::uint32_t>(c.Int());
  t.cuts = static_cast<std::uint32_t>(c.Int());
  t.incision_length_m = c.Real();
  t.line_deviation_max_m = c.Real();
  t.line_deviation_sum_m = c.Real();
  c.Real();  // line_deviation_mean_m: derived from the sum and cutting_ticks
  t.cutting_ticks = c.Uint();
  t.ticks = c.Uint();
  r.layer_names = store_codec::SplitNames(c.Text());
  r.targets.depth_m = c.Real();
  const std::array<double, 4> line = {c.Real(), c.Real(), c.Real(), c.Real()};  // braces: read in order
  if (!std::isnan(line[0])) r.targets.line_m = line;
  row.recording_path = c.Text();
  row.updated_unix_ms = c.Int();
  return row;
}

void BindRecording(Statement& s, const StoredRecording& row) {
  Binder(s)
      .Text(row.path)
      .Text(row.session_id)
      .Text(row.run_id)
      .Uint(row.trial)
      .Text(row.trainee)
      .Text(row.class_name)
      .Text(row.scene)
      .Int(row.started_unix_ms)
      .OptInt(row.ended_unix_ms)
      .Uint(row.ticks)
      .Uint(row.bytes)
      .Text(row.status);
}

StoredRecording ReadRecording(const Statement& s) {
  Cursor c(s);
  StoredRecording row;
  row.path = c.Text();
  row.session_id = c.Text();
  row.run_id = c.Text();
  row.trial = c.Uint();
  row.trainee = c.Text();
  row.class_name = c.Text();
  row.scene = c.Text();
  row.started_unix_ms = c.Int();
  row.ended_unix_ms = c.OptInt();
  row.ticks = c.Uint();
  row.bytes = c.Uint();
  row.status = c.Text();
  return row;
}

}  // namespace hapsim::service::store_internal
