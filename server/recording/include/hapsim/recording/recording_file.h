// One trial recording file being written: the file header on creation,
// then whole records appended with write(2). Once write() returned, a
// record survives a kill -9 of the server (it is in the OS's page cache);
// Sync() (fdatasync) makes it survive a power loss too.
#pragma once
#include <cstdint>
#include <span>
#include <string>

#include "hapsim/recording/recording_format.h"

namespace hapsim::service {

class RecordingFile {
 public:
  // A new file (never overwrites one: throws std::runtime_error naming the
  // path and errno's text), its header written.
  static RecordingFile Create(const std::string& path, const RecordingHeader& header);
  // An existing file cut back to `valid_bytes` (the end of its last good
  // record, from ReadRecording) to append after it.
  static RecordingFile Reopen(const std::string& path, std::uint64_t valid_bytes);

  RecordingFile(RecordingFile&& other) noexcept;
  RecordingFile& operator=(RecordingFile&& other) noexcept;
  RecordingFile(const RecordingFile&) = delete;
  RecordingFile& operator=(const RecordingFile&) = delete;
  ~RecordingFile();

  // false (errno's text in *error) when the bytes could not all be written.
  bool Append(std::span<const std::uint8_t> bytes, std::string* error);
  bool Sync(std::string* error);
  const std::string& path() const { return path_; }
  std::uint64_t bytes() const { return bytes_; }

 private:
  RecordingFile(std::string path, int fd, std::uint64_t bytes) : path_(std::move(path)), fd_(fd), bytes_(bytes) {}
  std::string path_;
  int fd_ = -1;
  std::uint64_t bytes_ = 0;
};

}  // namespace hapsim::service
