// dds::SessionPartition: a session id maps one-to-one onto a plain DDS
// partition name that matches only itself (Cyclone reads '*' and '?' as
// patterns and has no escape).
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstring>
#include <set>
#include <string>
#include <thread>

#include "hapsim/dds/dds.h"
#include "haptics.h"
#include "test_dds_domain.h"

namespace hapsim::dds {
namespace {

bool IsPlain(const std::string& name) {
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

TEST(SessionPartition, PlainIdsKeepTheirNameBehindTheFixedPrefix) {
  EXPECT_EQ(SessionPartition("trainee-1"), "hapsim_s_trainee-1");
  EXPECT_EQ(SessionPartition("AbZ09"), "hapsim_s_AbZ09");
}

TEST(SessionPartition, EveryOtherByteIsEscapedSoNoNameIsAPattern) {
  EXPECT_EQ(SessionPartition("a*"), "hapsim_s_a_2A");
  EXPECT_EQ(SessionPartition("?"), "hapsim_s__3F");
  EXPECT_EQ(SessionPartition("a_b"), "hapsim_s_a_5Fb");  // '_' escaped too: "a_5F" cannot collide with "a_"
  EXPECT_EQ(SessionPartition("\xff."), "hapsim_s__FF_2E");
  for (const std::string id : {"*", "a?b", "x.y", "sp ace", "\x01", "é"}) {
    const auto name = SessionPartition(id);
    EXPECT_TRUE(IsPlain(name)) << name;
    EXPECT_EQ(name.find_first_of("*?"), std::string::npos);
  }
}

TEST(SessionPartition, DistinctIdsGetDistinctPartitions) {
  // Every id of up to two characters over an alphabet with the tricky ones.
  const std::string alphabet = "a_5F*?-.";
  std::set<std::string> ids, names;
  ids.insert("");
  for (char c1 : alphabet) {
    ids.insert(std::string(1, c1));
    for (char c2 : alphabet) ids.insert(std::string{c1, c2});
  }
  for (const auto& id : ids) names.insert(SessionPartition(id));
  EXPECT_EQ(names.size(), ids.size());
}

// On a real domain: a reader in the partition of "a*" receives nothing a
// writer in the partition of "ab" publishes, and vice versa; the same id
// on both sides does communicate (so the silence is the partition's doing).
TEST(SessionPartition, AWildcardIdMatchesOnlyItselfOnTheWire) {
  const std::uint32_t domain = test::ClaimTestDdsDomain();
  Participant p({domain, ""});
  auto count_received = [&](const std::string& writer_id, const std::string& reader_id) {
    Writer<hapsim_dds_StylusPose> w(p, &hapsim_dds_StylusPose_desc, "hapsim_StylusPose", SessionPartition(writer_id));
    Reader<hapsim_dds_StylusPose> r(p, &hapsim_dds_StylusPose_desc, "hapsim_StylusPose", SessionPartition(reader_id));
    hapsim_dds_StylusPose pose{};
    pose.quat_wxyz[0] = 1.0;
    std::array<hapsim_dds_StylusPose, 16> got;
    std::size_t received = 0;
    for (int i = 0; i < 300 && received < 20; ++i) {
      pose.seq = static_cast<std::uint64_t>(i);
      w.Write(pose);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      received += r.Take(got);
    }
    return received;
  };
  EXPECT_GE(count_received("a*", "a*"), 20u);
  EXPECT_EQ(count_received("ab", "a*"), 0u);
  EXPECT_EQ(count_received("a*", "ab"), 0u);
  EXPECT_EQ(count_received("a?", "ab"), 0u);
}

}  // namespace
}  // namespace hapsim::dds
