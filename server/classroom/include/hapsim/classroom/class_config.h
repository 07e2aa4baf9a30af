// The classroom configuration (--class-config FILE, TOML): the classes, the
// sessions of each (created when the server starts) and the bearer tokens
// with their roles. docs/classroom.md documents the format with an example;
// deploy/make-class.sh writes one with fresh tokens.
//
//   [[class]]
//   name = "acu-101"
//   target_depth_m = 0.012     # optional: acupuncture target needle depth
//   target_line_m = [-0.01, 0, 0.01, 0]   # optional: cutting target line x0, y0, x1, y1
//   [[class.session]]
//   id = "t1"                 # session id, unique across classes
//   scene = "acupuncture"     # default "tissue_block"
//   trainee = "alice"         # shown to the instructor (the session's owner)
//
//   [[token]]
//   name = "alice"            # who holds it (logged; the token itself never is)
//   role = "trainee"          # instructor | trainee | observer
//   class = "acu-101"
//   sessions = ["t1"]         # trainee only: the sessions it drives and views
//   sha256 = "<64 hex>"       # SHA-256 of the token (or: token = "..." in plain, >= 16 characters)
#pragma once
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "hapsim/classroom/trial_tracker.h"

namespace hapsim::service {

enum class Role { kInstructor, kTrainee, kObserver };
const char* RoleName(Role role);

struct ClassSession {
  std::string id;
  std::string scene = "tissue_block";
  std::string trainee;
};

struct ClassDef {
  std::string name;
  std::vector<ClassSession> sessions;
  TrialTargets targets;  // target_depth_m, target_line_m: what its trials are measured against
  bool Has(std::string_view session_id) const { return Find(session_id) != nullptr; }
  const ClassSession* Find(std::string_view session_id) const;  // nullptr: not in this class
};

struct TokenDef {
  std::string name;
  Role role = Role::kObserver;
  std::string class_name;
  std::vector<std::string> sessions;  // trainee: its own sessions; others: empty (the whole class)
  std::string sha256_hex;             // lower-case SHA-256 of the token
};

struct ClassConfig {
  std::vector<ClassDef> classes;
  std::vector<TokenDef> tokens;
  std::vector<std::string> warnings;  // accepted but worth a log line (plain tokens)
};

// A config that cannot be used, with where and why: "FILE:LINE:COL: what".
class ClassConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses and checks a config: TOML syntax, known keys only, unique class
// names and session ids (valid ids, known scenes), tokens with a known role,
// an existing class, trainee sessions inside that class, a 64-hex sha256 or
// a plain token of >= 16 characters, and no token listed twice. Throws
// ClassConfigError naming the first problem; `origin` names the text in it.
ClassConfig ParseClassConfig(std::string_view toml_text, std::string_view origin);
ClassConfig LoadClassConfig(const std::string& path);  // reads the file, then ParseClassConfig

// Lower-case hex SHA-256 of `text` (what a config's sha256 holds).
std::string Sha256Hex(std::string_view text);

}  // namespace hapsim::service
