// Recordings: written frames read back equal; damage is named, not crashed on.
#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <google/protobuf/util/message_differencer.h>

#include "hapsim/viewer/frame_log.h"
#include "render_test_util.h"

namespace hapsim::viewer {
namespace {

std::string TempPath(const char* name) { return ::testing::TempDir() + name; }

TEST(FrameLog, FramesReadBackEqual) {
  const std::string path = TempPath("frames.log");
  FrameLogWriter writer;
  std::string error;
  ASSERT_TRUE(writer.Open(path, &error)) << error;
  auto key = gui::testing::GridKeyframe(4, 0.01, "skin");
  hapsim::v1::Frame delta;
  delta.set_seq(1);
  delta.mutable_delta()->add_index_gaps(3);
  for (const int dq : {1, -2, 3}) delta.mutable_delta()->add_position_dq(dq);
  ASSERT_TRUE(writer.Write(key));
  ASSERT_TRUE(writer.Write(delta));
  std::vector<hapsim::v1::Frame> frames;
  ASSERT_TRUE(ReadFrameLog(path, &frames, &error)) << error;
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(frames[0], key));
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(frames[1], delta));
}

TEST(FrameLog, DamagedRecordingsAreRefusedWithTheReason) {
  const std::string path = TempPath("damaged.log");
  std::string error;
  std::vector<hapsim::v1::Frame> frames;
  std::ofstream(path) << "not a recording";
  EXPECT_FALSE(ReadFrameLog(path, &frames, &error));
  EXPECT_NE(error.find("not a hapsim frame recording"), std::string::npos) << error;
  {
    FrameLogWriter writer;
    ASSERT_TRUE(writer.Open(path, &error));
    ASSERT_TRUE(writer.Write(gui::testing::GridKeyframe(3, 0.01, "skin")));
  }
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() - 5);
  EXPECT_FALSE(ReadFrameLog(path, &frames, &error));
  EXPECT_NE(error.find("frame 0 is truncated"), std::string::npos) << error;
  std::ofstream(path, std::ios::binary | std::ios::trunc) << std::string("HSFRAME1\xff\xff\xff\xff", 12);
  EXPECT_FALSE(ReadFrameLog(path, &frames, &error));
  EXPECT_NE(error.find("max 64 MiB"), std::string::npos) << error;
  // A length within 64 MiB but past the end of the file: truncated (the
  // reader compares the claim with what is left before allocating for it).
  std::istringstream short_stream(std::string("HSFRAME1\xff\xff\xff\x03", 12) + "ten bytes.");
  EXPECT_FALSE(ReadFrameLog(short_stream, "stream", &frames, &error));
  EXPECT_EQ(error, "stream: frame 0 is truncated");
  EXPECT_FALSE(ReadFrameLog(TempPath("missing.log"), &frames, &error));
  EXPECT_NE(error.find("cannot read"), std::string::npos) << error;
}

}  // namespace
}  // namespace hapsim::viewer
