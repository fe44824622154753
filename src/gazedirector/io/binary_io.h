#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <istream>
#include <ostream>
#include <span>
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

// An array that is read where it lies in a mapped file (MappedFile) has its
// values start on a multiple of this many bytes from the file's start: zero
// bytes of padding, then its count, then its values.
constexpr std::size_t kArrayAlignment = 64;

namespace internal {
inline std::size_t PaddingBeforeCount(std::uintptr_t offset) {
  return (kArrayAlignment - (offset + sizeof(uint64_t)) % kArrayAlignment) % kArrayAlignment;
}

// The count that opens an array in `rest`, consumed; false when it is cut
// short or its values would be more than `max_count` or run past the end.
template <typename T>
bool ReadCount(std::span<const std::byte>& rest, uint64_t max_count, uint64_t& count) {
  if (rest.size() < sizeof count) return false;
  std::memcpy(&count, rest.data(), sizeof count);
  rest = rest.subspan(sizeof count);
  return count <= max_count && count <= rest.size() / sizeof(T);
}
}  // namespace internal

template <typename T>
void WriteAlignedVector(std::ostream& out, const std::vector<T>& values) {
  static_assert(kArrayAlignment % alignof(T) == 0);
  const char zeros[kArrayAlignment] = {};
  out.write(zeros, static_cast<std::streamsize>(internal::PaddingBeforeCount(static_cast<std::uintptr_t>(out.tellp()))));
  WriteVector(out, values);
}

// ReadVector from the bytes of a mapped file: the array that opens `rest` is
// copied into `values` and consumed.
template <typename T>
bool ReadVector(std::span<const std::byte>& rest, std::vector<T>& values, uint64_t max_count) {
  uint64_t count = 0;
  if (!internal::ReadCount<T>(rest, max_count, count)) return false;
  values.resize(count);
  std::memcpy(values.data(), rest.data(), count * sizeof(T));
  rest = rest.subspan(count * sizeof(T));
  return true;
}

// An array written by WriteAlignedVector, viewed where it lies in a mapping
// (which starts on a page, so the file's offsets keep their alignment).
template <typename T>
bool ViewAlignedVector(std::span<const std::byte>& rest, std::span<const T>& values, uint64_t max_count) {
  const std::size_t padding = internal::PaddingBeforeCount(reinterpret_cast<std::uintptr_t>(rest.data()));
  if (rest.size() < padding) return false;
  rest = rest.subspan(padding);
  uint64_t count = 0;
  if (!internal::ReadCount<T>(rest, max_count, count)) return false;
  values = {reinterpret_cast<const T*>(rest.data()), count};
  rest = rest.subspan(count * sizeof(T));
  return true;
}

}  // namespace gazedirector
