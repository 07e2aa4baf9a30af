// The rows of the results database (docs/recording.md, "The results database"): one struct per
// table, each field one column unless said otherwise. Times are wall-clock
// milliseconds since the Unix epoch (`_unix_ms`), simulation times seconds
// (`_sim_s`); a NaN double is stored as NULL and read back as NaN.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hapsim/classroom/trial_book.h"

namespace hapsim::service {

// Table `sessions`: a live session, to bring back after a restart.
// Key: id. Removed when the session closes.
struct StoredSession {
  std::string id;                        // id TEXT PRIMARY KEY
  std::string scene;                     // scene TEXT
  std::map<std::string, double> params;  // params TEXT: "name=value;name=value", values %.17g (exact)
  std::string owner;                     // owner TEXT: the trainee driving it
  std::string class_name;                // class_name TEXT ("" outside a class)
  std::string run_id;                    // run_id TEXT: this incarnation of the session
  std::int64_t created_unix_ms = 0;      // created_unix_ms INTEGER
  std::string recording_path;            // recording_path TEXT: its open trial file ("" none)
};

// Table `trials`: one row per trial, upserted while it runs and finalised
// when it ends. Key: (session_id, run_id, trial). Columns, from `record`:
//   session_id, trainee, scene TEXT; trial INTEGER (TrialStats::trial);
//   end_state TEXT: "running" | "reset" | "closed" (TrialRecord::end);
//   start_sim_s, last_sim_s, first_contact_sim_s (NULL: no contact), peak_force_N,
//   max_tip_depth_m REAL; peak_force_in_layer_N TEXT (comma-separated %.17g, one per layer slot);
//   layers_pierced_mask (bit L: layer L punctured), punctures, cuts INTEGER;
//   incision_length_m, line_deviation_max_m, line_deviation_sum_m REAL;
//   line_deviation_mean_m REAL (derived: sum / cutting_ticks, for SQL readers; not read back);
//   cutting_ticks, ticks INTEGER; layer_names TEXT ("|"-joined, '|' and '%' escaped as %7C, %25);
//   target_depth_m REAL (NULL: none); target_line_x0_m, _y0_m, _x1_m, _y1_m REAL (NULL: no line).
// and from this struct: run_id, class_name, recording_path TEXT; updated_unix_ms INTEGER.
struct StoredTrial {
  TrialRecord record;          // what FormatTrialsCsv takes
  std::string run_id;          // the session's incarnation: trial numbers restart in each
  std::string class_name;      // "" outside a class
  std::string recording_path;  // the trial's recording file ("" none)
  std::int64_t updated_unix_ms = 0;
};

// Table `score_sheets`: one expert's sheet for one session, replayed into
// ScoreBook::Submit on restart (in submission order, so the book ends up as
// it was). Key: (session_id, expert); a resubmission replaces the row.
struct StoredScoreSheet {
  std::string session_id;              // session_id TEXT
  std::string scene;                   // scene TEXT: decides the scoring scheme
  std::string expert;                  // expert TEXT
  std::vector<double> indicators;      // indicators TEXT: comma-separated %.17g (exact)
  std::int64_t submitted_unix_ms = 0;  // submitted_unix_ms INTEGER
  // (submit_seq INTEGER, not in the struct: orders the rows, increasing across restarts)
};

// Table `class_roster`: who was seen in which class's session, and when.
// Key: (class_name, session_id, trainee).
struct StoredRosterEntry {
  std::string class_name;               // class_name TEXT
  std::string session_id;               // session_id TEXT
  std::string trainee;                  // trainee TEXT
  std::int64_t first_seen_unix_ms = 0;  // first_seen_unix_ms INTEGER: the earliest noted
  std::int64_t last_seen_unix_ms = 0;   // last_seen_unix_ms INTEGER: the latest noted
};

// Table `recordings`: the index of trial recordings. Key: path.
struct StoredRecording {
  std::string path;                           // path TEXT PRIMARY KEY
  std::string session_id;                     // session_id TEXT
  std::string run_id;                         // run_id TEXT
  std::uint64_t trial = 0;                    // trial INTEGER
  std::string trainee;                        // trainee TEXT
  std::string class_name;                     // class_name TEXT
  std::string scene;                          // scene TEXT
  std::int64_t started_unix_ms = 0;           // started_unix_ms INTEGER
  std::optional<std::int64_t> ended_unix_ms;  // ended_unix_ms INTEGER: NULL while open
  std::uint64_t ticks = 0;                    // ticks INTEGER: recorded so far
  std::uint64_t bytes = 0;                    // bytes INTEGER: file size so far
  std::string status = "open";                // status TEXT: "open" | "closed" | "deleted"
};

}  // namespace hapsim::service
