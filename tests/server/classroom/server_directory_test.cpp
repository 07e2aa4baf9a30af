// The server directory (--directory): what a site's list of servers must be
// for Locate to be trusted — every server once, every address dialable —
// and errors that say where the file is wrong.
#include "hapsim/classroom/server_directory.h"

#include <gtest/gtest.h>

#include <string>

namespace hapsim::service {
namespace {

// The parse error's message ("" when it parses).
std::string DirectoryErrorOf(const std::string& toml) {
  try {
    ParseServerDirectory(toml, "dir.toml");
  } catch (const ClassConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ServerDirectory, ListsEveryServerInTheFilesOrder) {
  const auto d = ParseServerDirectory(R"(
[[server]]
name = "hapsim-0"
address = "hapsim-0.hapsim:50051"
[[server]]
name = "hapsim-1"
address = "10.0.0.2:50051"
[[server]]
name = "v6"
address = "[fd00::3]:443"
)",
                                      "dir.toml");
  ASSERT_EQ(d.servers.size(), 3u);
  EXPECT_EQ(d.servers[0].name, "hapsim-0");
  EXPECT_EQ(d.servers[0].address, "hapsim-0.hapsim:50051");
  EXPECT_EQ(d.servers[2].address, "[fd00::3]:443");
  ASSERT_NE(d.Find("hapsim-1"), nullptr);
  EXPECT_EQ(d.Find("hapsim-1")->address, "10.0.0.2:50051");
  EXPECT_EQ(d.Find("hapsim-2"), nullptr);
}

TEST(ServerDirectory, AnEmptyDirectoryIsRefused) {
  EXPECT_EQ(DirectoryErrorOf(""), "dir.toml: no [[server]]: a directory lists at least one server");
}

TEST(ServerDirectory, AServerListedTwiceIsRefusedWithItsLine) {
  const auto error =
      DirectoryErrorOf("[[server]]\nname = \"a\"\naddress = \"h1:1\"\n[[server]]\nname = \"a\"\naddress = \"h2:1\"\n");
  EXPECT_NE(error.find("dir.toml:4:1: server 'a' is listed twice"), std::string::npos) << error;
}

TEST(ServerDirectory, AnAddressListedTwiceIsRefused) {
  const auto error =
      DirectoryErrorOf("[[server]]\nname = \"a\"\naddress = \"h:1\"\n[[server]]\nname = \"b\"\naddress = \"h:1\"\n");
  EXPECT_NE(error.find("address 'h:1' is listed twice (server 'b')"), std::string::npos) << error;
}

TEST(ServerDirectory, AnAddressMustBeHostAndAPortInRange) {
  for (const std::string bad :
       {"host", "host:", ":50051", "host:0", "host:65536", "host:123456", "host:5x", "h st:1"}) {
    const auto error = DirectoryErrorOf("[[server]]\nname = \"a\"\naddress = \"" + bad + "\"\n");
    EXPECT_NE(error.find("dir.toml:3:11: address '" + bad + "' of server 'a' must be host:port (port 1-65535)"),
              std::string::npos)
        << bad << ": " << error;
  }
  EXPECT_EQ(DirectoryErrorOf("[[server]]\nname = \"a\"\naddress = \"h:65535\"\n"), "");
  EXPECT_EQ(DirectoryErrorOf("[[server]]\nname = \"a\"\naddress = \"h:1\"\n"), "");
}

TEST(ServerDirectory, ANameMustBeShortAndPlain) {
  EXPECT_NE(
      DirectoryErrorOf("[[server]]\nname = \"a b\"\naddress = \"h:1\"\n").find("server name 'a b' must be 1-63 of"),
      std::string::npos);
  EXPECT_NE(
      DirectoryErrorOf("[[server]]\nname = \"" + std::string(64, 'x') + "\"\naddress = \"h:1\"\n").find("must be 1-63"),
      std::string::npos);
  EXPECT_EQ(DirectoryErrorOf("[[server]]\nname = \"" + std::string(63, 'x') + "\"\naddress = \"h:1\"\n"), "");
}

TEST(ServerDirectory, ATypoInAKeyIsAnErrorNotASilentDefault) {
  const auto error = DirectoryErrorOf("[[server]]\nname = \"a\"\nadress = \"h:1\"\n");
  EXPECT_NE(error.find("unknown key 'adress' in [[server]] (known: name, address)"), std::string::npos) << error;
  EXPECT_NE(DirectoryErrorOf("[[servers]]\nname = \"a\"\n").find("unknown key 'servers' in the directory"),
            std::string::npos);
}

TEST(ServerDirectory, AMissingFileSaysWhichFile) {
  try {
    LoadServerDirectory("/nonexistent/dir.toml");
    FAIL() << "loaded a file that does not exist";
  } catch (const ClassConfigError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/dir.toml: cannot read the server directory");
  }
}

}  // namespace
}  // namespace hapsim::service
