// The migration steps. Append only: a released step is never edited.
// Columns are documented in hapsim/store/stored_rows.h and docs/recording.md.
#include "hapsim/store/schema.h"

namespace hapsim::service {

const std::vector<SchemaStep>& SchemaSteps() {
  static const std::vector<SchemaStep> steps = {
      {1, R"sql(
CREATE TABLE sessions (
  id TEXT PRIMARY KEY,
  scene TEXT NOT NULL,
  params TEXT NOT NULL,
  owner TEXT NOT NULL,
  class_name TEXT NOT NULL,
  run_id TEXT NOT NULL,
  created_unix_ms INTEGER NOT NULL,
  recording_path TEXT NOT NULL
);
CREATE TABLE trials (
  session_id TEXT NOT NULL,
  run_id TEXT NOT NULL,
  trial INTEGER NOT NULL,
  trainee TEXT NOT NULL,
  scene TEXT NOT NULL,
  class_name TEXT NOT NULL,
  end_state TEXT NOT NULL,
  start_sim_s REAL,
  last_sim_s REAL,
  first_contact_sim_s REAL,
  peak_force_N REAL,
  max_tip_depth_m REAL,
  peak_force_in_layer_N TEXT NOT NULL,
  layers_pierced_mask INTEGER NOT NULL,
  punctures INTEGER NOT NULL,
  cuts INTEGER NOT NULL,
  incision_length_m REAL,
  line_deviation_max_m REAL,
  line_deviation_sum_m REAL,
  line_deviation_mean_m REAL,
  cutting_ticks INTEGER NOT NULL,
  ticks INTEGER NOT NULL,
  layer_names TEXT NOT NULL,
  target_depth_m REAL,
  target_line_x0_m REAL,
  target_line_y0_m REAL,
  target_line_x1_m REAL,
  target_line_y1_m REAL,
  recording_path TEXT NOT NULL,
  updated_unix_ms INTEGER NOT NULL,
  PRIMARY KEY (session_id, run_id, trial)
);
CREATE TABLE score_sheets (
  session_id TEXT NOT NULL,
  expert TEXT NOT NULL,
  scene TEXT NOT NULL,
  indicators TEXT NOT NULL,
  submitted_unix_ms INTEGER NOT NULL,
  submit_seq INTEGER NOT NULL,
  PRIMARY KEY (session_id, expert)
);
CREATE TABLE class_roster (
  class_name TEXT NOT NULL,
  session_id TEXT NOT NULL,
  trainee TEXT NOT NULL,
  first_seen_unix_ms INTEGER NOT NULL,
  last_seen_unix_ms INTEGER NOT NULL,
  PRIMARY KEY (class_name, session_id, trainee)
);
CREATE TABLE recordings (
  path TEXT PRIMARY KEY,
  session_id TEXT NOT NULL,
  run_id TEXT NOT NULL,
  trial INTEGER NOT NULL,
  trainee TEXT NOT NULL,
  class_name TEXT NOT NULL,
  scene TEXT NOT NULL,
  started_unix_ms INTEGER NOT NULL,
  ended_unix_ms INTEGER,
  ticks INTEGER NOT NULL,
  bytes INTEGER NOT NULL,
  status TEXT NOT NULL
);
CREATE INDEX recordings_by_end ON recordings (ended_unix_ms);
)sql"},
  };
  return steps;
}

}  // namespace hapsim::service
