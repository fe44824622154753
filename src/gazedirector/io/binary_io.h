#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <vector>

namespace gazedirector {

// Caches of derived data store plain arrays: a 64-bit count, then the values
// as they lie in memory (caches are read back on the machine that wrote them).
template <typename T>
void WriteVector(std::ostream& out, const std::vector<T>& values) {
  const uint64_t count = values.size();
  out.write(reinterpret_cast<const char*>(&count), sizeof count);
  out.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(count * sizeof(T)));
}

// False when the stream ends early or holds more than `max_count` values.
template <typename T>
bool ReadVector(std::istream& in, std::vector<T>& values, uint64_t max_count) {
  uint64_t count = 0;
  in.read(reinterpret_cast<char*>(&count), sizeof count);
  if (!in || count > max_count) return false;
  values.resize(count);
  in.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(count * sizeof(T)));
  return static_cast<bool>(in);
}

}  // namespace gazedirector
