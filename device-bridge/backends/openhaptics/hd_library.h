// The OpenHaptics HD runtime, loaded at run time: every build has the
// OpenHaptics backend, and a lab installs only the vendor's runtime (or
// points --hd-library at it). Loading fails with a message naming the
// library and what is missing; nothing is called before every function
// the backend needs has been found.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>

#include "backends/openhaptics/hd_api.h"

namespace hapsim::bridge {

// A device that cannot be used: the library is missing, no device answers,
// it needs calibration, or it faulted. The message says what to do.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class HdLibrary {
 public:
  // `path`: a file name searched like any shared library ("libHD.so") or a
  // path. Throws DeviceError naming it when it cannot be loaded or lacks a
  // function.
  static std::shared_ptr<const HdLibrary> Load(const std::string& path);
  ~HdLibrary();
  HdLibrary(const HdLibrary&) = delete;
  HdLibrary& operator=(const HdLibrary&) = delete;

  const hd::Functions& api() const { return api_; }
  const std::string& path() const { return path_; }
  // "HD_FORCE_ERROR (0x0204): <the library's description>".
  std::string Describe(const HDErrorInfo& error) const;

 private:
  HdLibrary(void* handle, std::string path) : handle_(handle), path_(std::move(path)) {}
  void* handle_;
  std::string path_;
  hd::Functions api_{};
};

}  // namespace hapsim::bridge
