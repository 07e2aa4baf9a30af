// The class config: a good one parses into classes and tokens; every kind of
// mistake stops the server at start with the file, line and column and what
// is wrong (the server refuses to start: a half-read config could let the
// wrong people in).
#include "hapsim/classroom/class_config.h"

#include <gtest/gtest.h>

#include "hapsim/classroom/access_policy.h"
#include "hapsim/runtime/errors.h"

namespace hapsim::service {
namespace {

constexpr const char* kGood = R"(
[[class]]
name = "acu-101"
[[class.session]]
id = "t1"
scene = "acupuncture"
trainee = "alice"
[[class.session]]
id = "t2"

[[token]]
name = "dr-li"
role = "instructor"
class = "acu-101"
sha256 = "5e884898da28047151d0e56f8dc6292773603d0d6aabbdd62a11ef721d1542d8"

[[token]]
name = "alice"
role = "trainee"
class = "acu-101"
sessions = ["t1"]
token = "alice-secret-0123456789"
)";

TEST(ClassConfig, AGoodConfigParsesIntoClassesAndTokens) {
  const ClassConfig c = ParseClassConfig(kGood, "good.toml");
  ASSERT_EQ(c.classes.size(), 1u);
  ASSERT_EQ(c.classes[0].sessions.size(), 2u);
  EXPECT_EQ(c.classes[0].sessions[0].scene, "acupuncture");
  EXPECT_EQ(c.classes[0].sessions[0].trainee, "alice");
  EXPECT_EQ(c.classes[0].sessions[1].scene, "tissue_block");  // the default
  ASSERT_EQ(c.tokens.size(), 2u);
  EXPECT_EQ(c.tokens[0].role, Role::kInstructor);
  EXPECT_EQ(c.tokens[1].role, Role::kTrainee);
  EXPECT_EQ(c.tokens[1].sessions, std::vector<std::string>{"t1"});
  // A plain token is kept only as its hash, with a warning naming the hash to use.
  EXPECT_EQ(c.tokens[1].sha256_hex, Sha256Hex("alice-secret-0123456789"));
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find(c.tokens[1].sha256_hex), std::string::npos);
}

// FIPS 180-2 test vector: SHA-256("abc").
// HTTP's auth schemes are case-insensitive (RFC 9110 11.1) and the token
// follows one or more spaces: any spelling of "Bearer" lets alice in; a
// wrong scheme, no token or a wrong token does not.
TEST(ClassConfig, TheBearerSchemeIsReadInAnyCaseAndOnlyTheRightTokenGetsIn) {
  const AccessPolicy policy(ParseClassConfig(kGood, "good.toml"));
  for (const std::string scheme : {"Bearer ", "bearer ", "BEARER ", "bEaReR   "}) {
    const std::string value = scheme + "alice-secret-0123456789";
    const auto who = policy.Authenticate(&value);
    ASSERT_TRUE(who.has_value()) << value;
    EXPECT_EQ(who->name, "alice") << value;
  }
  for (const std::string bad : {"Basic alice-secret-0123456789", "Bearer", "Bearer ", "Beareralice-secret-0123456789",
                                "Bearer alice-secret-012345678", "Token alice-secret-0123456789"}) {
    EXPECT_THROW(policy.Authenticate(&bad), ServiceError) << bad;
  }
}

TEST(ClassConfig, Sha256MatchesTheStandardTestVector) {
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

std::string ErrorOf(const std::string& text) {
  try {
    ParseClassConfig(text, "bad.toml");
  } catch (const ClassConfigError& e) {
    return e.what();
  }
  return "(accepted)";
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(ClassConfig, EveryMistakeIsNamedWithItsPlace) {
  struct Case {
    std::string text;
    std::string expected;  // in the message
  };
  const Case cases[] = {
      {"[[class]\nname = 1", "bad.toml:1:"},                                                 // TOML syntax
      {"", "no [[class]]"},
      {Replace(kGood, "trainee = \"alice\"", "trainee = \"alice\"\ncolour = \"red\""), "bad.toml:8:10: unknown key 'colour'"},
      {Replace(kGood, "role = \"instructor\"", "role = \"admin\""), "unknown role 'admin'"},
      {Replace(kGood, "sessions = [\"t1\"]\n", ""), "trainee token 'alice' needs 'sessions'"},
      {Replace(kGood, "sessions = [\"t1\"]", "sessions = [\"t9\"]"), "session 't9' is not in class 'acu-101'"},
      {Replace(kGood, "class = \"acu-101\"\nsessions", "class = \"acu-999\"\nsessions"), "no class 'acu-999'"},
      {Replace(kGood, "alice-secret-0123456789", "short"), "shorter than 16 characters"},
      {Replace(kGood, "sha256 = \"5e88", "sha256 = \"XX88"), "64 lower-case hex digits"},
      {Replace(kGood, "id = \"t2\"", "id = \"t1\""), "session 't1' is listed twice"},
      {Replace(kGood, "scene = \"acupuncture\"", "scene = \"heart\""), "unknown scene 'heart'"},
      {Replace(kGood, "id = \"t2\"", "id = \"t 2\""), "must be 1-63 characters"},
      {Replace(kGood, "token = \"alice-secret-0123456789\"",
               "sha256 = \"5e884898da28047151d0e56f8dc6292773603d0d6aabbdd62a11ef721d1542d8\""),
       "the same as an earlier one"},
      {Replace(kGood, "role = \"instructor\"\nclass = \"acu-101\"",
               "role = \"instructor\"\nclass = \"acu-101\"\nsessions = [\"t1\"]"),
       "covers its whole class"},
      {Replace(kGood, "token = \"alice-secret-0123456789\"", ""), "exactly one of 'sha256' and 'token'"},
      {Replace(kGood, "name = \"acu-101\"", "name = 101"), "'name' must be a string"},
  };
  for (const Case& c : cases) {
    const std::string message = ErrorOf(c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << message;
  }
}

TEST(ClassConfig, AMissingFileIsAClearError) {
  try {
    LoadClassConfig("/nonexistent/class.toml");
    FAIL();
  } catch (const ClassConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/class.toml: cannot read"), std::string::npos);
  }
}

}  // namespace
}  // namespace hapsim::service
