// A minimal JSON emitter for reports (no JSON library in the dependency
// set): nested objects and arrays, two-space indentation, strings escaped,
// non-finite numbers written as null.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace hapsim::bridge {

class JsonWriter {
 public:
  // key: the member name inside an object; nullptr inside an array or at the top.
  void BeginObject(const char* key = nullptr);
  void EndObject();
  void BeginArray(const char* key);
  void EndArray();
  void Field(const char* key, std::uint64_t value);
  void Field(const char* key, double value);
  void Field(const char* key, bool value);
  void Field(const char* key, const std::string& value);
  void Field(const char* key, const char* value) { Field(key, std::string(value)); }  // not the bool overload
  const std::string& text() const { return out_; }

 private:
  void Open(const char* key, char bracket);
  void Close(char bracket);
  void Prefix(const char* key);
  std::string out_;
  std::vector<bool> has_members_;  // per open scope
};

}  // namespace hapsim::bridge
