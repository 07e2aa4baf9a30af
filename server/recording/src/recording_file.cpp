#include "hapsim/recording/recording_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace hapsim::service {

namespace {

std::string ErrnoText(const std::string& what, const std::string& path) {
  return what + " " + path + ": " + std::strerror(errno);
}

}  // namespace

RecordingFile RecordingFile::Create(const std::string& path, const RecordingHeader& header) {
  const auto bytes = EncodeFileHeader(header);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0640);
  if (fd < 0) throw std::runtime_error(ErrnoText("cannot create recording", path));
  RecordingFile file(path, fd, 0);
  std::string error;
  if (!file.Append(bytes, &error)) throw std::runtime_error(error);
  return file;
}

RecordingFile RecordingFile::Reopen(const std::string& path, std::uint64_t valid_bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(ErrnoText("cannot reopen recording", path));
  RecordingFile file(path, fd, valid_bytes);
  if (::ftruncate(fd, static_cast<off_t>(valid_bytes)) != 0 ||
      ::lseek(fd, static_cast<off_t>(valid_bytes), SEEK_SET) < 0) {
    throw std::runtime_error(ErrnoText("cannot cut back the torn tail of recording", path));
  }
  return file;
}

RecordingFile::RecordingFile(RecordingFile&& other) noexcept
    : path_(std::move(other.path_)), fd_(other.fd_), bytes_(other.bytes_) {
  other.fd_ = -1;
}

RecordingFile& RecordingFile::operator=(RecordingFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    fd_ = other.fd_;
    bytes_ = other.bytes_;
    other.fd_ = -1;
  }
  return *this;
}

RecordingFile::~RecordingFile() {
  if (fd_ >= 0) ::close(fd_);
}

bool RecordingFile::Append(std::span<const std::uint8_t> bytes, std::string* error) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      *error = ErrnoText("cannot write recording", path_);
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  bytes_ += done;
  return true;
}

bool RecordingFile::Sync(std::string* error) {
  if (::fdatasync(fd_) == 0) return true;
  *error = ErrnoText("cannot sync recording", path_);
  return false;
}

}  // namespace hapsim::service
