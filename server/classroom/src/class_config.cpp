#include "hapsim/classroom/class_config.h"

#include <openssl/evp.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "hapsim/common/session_id.h"
#include "hapsim/core/scenes/scene.h"
#include "toml_checker.h"

namespace hapsim::service {

const char* RoleName(Role role) {
  switch (role) {
    case Role::kInstructor: return "instructor";
    case Role::kTrainee: return "trainee";
    case Role::kObserver: return "observer";
  }
  return "?";
}

const ClassSession* ClassDef::Find(std::string_view session_id) const {
  const auto found =
      std::find_if(sessions.begin(), sessions.end(), [&](const ClassSession& s) { return s.id == session_id; });
  return found == sessions.end() ? nullptr : &*found;
}

std::string Sha256Hex(std::string_view text) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(text.data(), text.size(), digest, &length, EVP_sha256(), nullptr) != 1) {
    throw std::runtime_error("SHA-256 failed (OpenSSL)");
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) {
    hex += kHex[digest[i] >> 4];
    hex += kHex[digest[i] & 15];
  }
  return hex;
}

namespace {

using Checker = TomlChecker<ClassConfigError>;

bool IsLowerHex64(const std::string& s) {
  return s.size() == 64 &&
         std::all_of(s.begin(), s.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

// A [[class]]'s optional target_depth_m and target_line_m.
void ParseClassTargets(const Checker& check, const toml::table& t, TrialTargets* targets) {
  if (const toml::node* depth = t.get("target_depth_m")) {
    const auto v = depth->value<double>();
    if (!v || !(*v > 0.0 && *v < 0.2)) check.Fail(*depth, "target_depth_m must be a number in (0, 0.2) m");
    targets->depth_m = *v;
  }
  if (const toml::array* line = check.Array(t, "target_line_m")) {
    if (line->size() != 4) check.Fail(*t.get("target_line_m"), "target_line_m is [x0, y0, x1, y1] in metres");
    for (std::size_t k = 0; k < 4; ++k) {
      const auto v = (*line)[k].value<double>();
      if (!v || !(std::abs(*v) < 1.0)) check.Fail((*line)[k], "target_line_m coordinates must be numbers within 1 m");
      targets->line_m[k] = *v;
    }
  }
}

// session_ids: every session id so far, across classes (ids are unique server-wide).
ClassSession ParseClassSession(const Checker& check, const toml::node& session_node,
                               const std::set<std::string>& scene_names, std::set<std::string>* session_ids) {
  const auto* st = session_node.as_table();
  if (!st) check.Fail(session_node, "each [[class.session]] must be a table");
  check.OnlyKeys(*st, {"id", "scene", "trainee"}, "[[class.session]]");
  ClassSession s;
  s.id = check.String(*st, "id", "[[class.session]]", true);
  if (!common::IsValidSessionId(s.id)) {
    check.Fail(*st->get("id"), "session id '" + s.id + "' must be 1-63 characters of [A-Za-z0-9_-]");
  }
  if (!session_ids->insert(s.id).second) check.Fail(*st->get("id"), "session '" + s.id + "' is listed twice");
  s.scene = check.String(*st, "scene", "[[class.session]]", false, "tissue_block");
  if (!scene_names.count(s.scene)) check.Fail(*st->get("scene"), "unknown scene '" + s.scene + "'");
  s.trainee = check.String(*st, "trainee", "[[class.session]]", false);
  return s;
}

ClassDef ParseClassTable(const Checker& check, const toml::node& class_node, const std::set<std::string>& scene_names,
                         std::set<std::string>* class_names, std::set<std::string>* session_ids) {
  const auto* t = class_node.as_table();
  if (!t) check.Fail(class_node, "each [[class]] must be a table");
  check.OnlyKeys(*t, {"name", "session", "target_depth_m", "target_line_m"}, "[[class]]");
  ClassDef def;
  def.name = check.String(*t, "name", "[[class]]", true);
  if (def.name.empty() || !common::IsValidSessionId(def.name)) {
    check.Fail(*t->get("name"), "class name '" + def.name + "' must be 1-63 characters of [A-Za-z0-9_-]");
  }
  if (!class_names->insert(def.name).second) check.Fail(*t->get("name"), "class '" + def.name + "' is listed twice");
  ParseClassTargets(check, *t, &def.targets);
  const toml::array* sessions = check.Array(*t, "session");
  if (!sessions || sessions->empty()) check.Fail(*t, "class '" + def.name + "' has no [[class.session]]");
  for (const auto& session_node : *sessions) {
    def.sessions.push_back(ParseClassSession(check, session_node, scene_names, session_ids));
  }
  return def;
}

Role ParseTokenRole(const Checker& check, const toml::table& t) {
  const std::string role = check.String(t, "role", "[[token]]", true);
  if (role == "instructor") return Role::kInstructor;
  if (role == "trainee") return Role::kTrainee;
  if (role == "observer") return Role::kObserver;
  check.Fail(*t.get("role"), "unknown role '" + role + "' (instructor, trainee or observer)");
}

// 'sessions': a trainee's own sessions, which must be in its class; other
// roles cover the whole class and must leave it out.
void ParseTokenSessions(const Checker& check, const toml::table& t, const ClassDef& cls, TokenDef* def) {
  if (const toml::array* sessions = check.Array(t, "sessions")) {
    for (const auto& s : *sessions) {
      const auto* id = s.as_string();
      if (!id) check.Fail(s, "'sessions' lists session ids (strings)");
      if (!cls.Has(id->get())) {
        check.Fail(s, "session '" + id->get() + "' is not in class '" + def->class_name + "'");
      }
      def->sessions.push_back(id->get());
    }
  }
  if (def->role == Role::kTrainee && def->sessions.empty()) {
    check.Fail(t, "trainee token '" + def->name + "' needs 'sessions' (the sessions it drives)");
  }
  if (def->role != Role::kTrainee && !def->sessions.empty()) {
    check.Fail(*t.get("sessions"), std::string(RoleName(def->role)) + " token '" + def->name +
                                       "' covers its whole class: leave 'sessions' out");
  }
}

// The token's sha256, given as such or hashed from a plain token (which earns a warning).
void ParseTokenSecret(const Checker& check, const toml::table& t, TokenDef* def, std::vector<std::string>* warnings) {
  const bool has_hash = t.contains("sha256"), has_plain = t.contains("token");
  if (has_hash == has_plain) check.Fail(t, "token '" + def->name + "' needs exactly one of 'sha256' and 'token'");
  if (has_hash) {
    def->sha256_hex = check.String(t, "sha256", "[[token]]", true);
    if (!IsLowerHex64(def->sha256_hex)) {
      check.Fail(*t.get("sha256"), "sha256 of token '" + def->name + "' must be 64 lower-case hex digits");
    }
  } else {
    const std::string plain = check.String(t, "token", "[[token]]", true);
    if (plain.size() < 16) check.Fail(*t.get("token"), "token '" + def->name + "' is shorter than 16 characters");
    def->sha256_hex = Sha256Hex(plain);
    warnings->push_back("token '" + def->name + "' is stored in plain text; prefer sha256 = \"" + def->sha256_hex +
                        "\"");
  }
}

// hashes: every token's sha256 so far (no token may be listed twice).
TokenDef ParseTokenTable(const Checker& check, const toml::node& token_node, const std::vector<ClassDef>& classes,
                         std::vector<std::string>* warnings, std::set<std::string>* hashes) {
  const auto* t = token_node.as_table();
  if (!t) check.Fail(token_node, "each [[token]] must be a table");
  check.OnlyKeys(*t, {"name", "role", "class", "sessions", "sha256", "token"}, "[[token]]");
  TokenDef def;
  def.name = check.String(*t, "name", "[[token]]", true);
  def.role = ParseTokenRole(check, *t);
  def.class_name = check.String(*t, "class", "[[token]]", true);
  const auto cls =
      std::find_if(classes.begin(), classes.end(), [&](const ClassDef& c) { return c.name == def.class_name; });
  if (cls == classes.end()) check.Fail(*t->get("class"), "no class '" + def.class_name + "'");
  ParseTokenSessions(check, *t, *cls, &def);
  ParseTokenSecret(check, *t, &def, warnings);
  if (!hashes->insert(def.sha256_hex).second) check.Fail(*t, "token '" + def.name + "' is the same as an earlier one");
  return def;
}

}  // namespace

ClassConfig ParseClassConfig(std::string_view text, std::string_view origin) {
  const Checker check(origin);
  const toml::table root = check.Parse(text);
  check.OnlyKeys(root, {"class", "token"}, "the config");
  std::set<std::string> scene_names;
  for (const auto& scene : core::SceneCatalog()) scene_names.insert(scene.name);

  ClassConfig config;
  std::set<std::string> class_names, session_ids;
  const toml::array* classes = check.Array(root, "class");
  if (!classes || classes->empty()) check.Fail("no [[class]]: a class config lists at least one class");
  for (const auto& class_node : *classes) {
    config.classes.push_back(ParseClassTable(check, class_node, scene_names, &class_names, &session_ids));
  }

  std::set<std::string> hashes;
  const toml::array* tokens = check.Array(root, "token");
  if (!tokens || tokens->empty()) check.Fail("no [[token]]: nobody could call the server");
  for (const auto& token_node : *tokens) {
    config.tokens.push_back(ParseTokenTable(check, token_node, config.classes, &config.warnings, &hashes));
  }
  return config;
}

ClassConfig LoadClassConfig(const std::string& path) {
  return ParseClassConfig(ReadConfigFile<ClassConfigError>(path, "class config"), path);
}

}  // namespace hapsim::service
