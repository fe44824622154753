#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>

namespace gazedirector {

// A file's bytes mapped read-only into memory, unmapped with the object.
// Pages are read as they are touched, so a large cache of which a process
// uses a little costs little. Files are replaced by renaming (AtomicOutput),
// never rewritten in place, so a mapping keeps the bytes it was opened with.
class MappedFile {
 public:
  // Nothing when the file cannot be opened or mapped, or is empty.
  static std::optional<MappedFile> Open(const std::filesystem::path& path);

  MappedFile(MappedFile&& other) noexcept;
  MappedFile& operator=(MappedFile&& other) noexcept;
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile();

  // Starts on a page boundary.
  std::span<const std::byte> bytes() const { return {data_, size_}; }

 private:
  MappedFile(const std::byte* data, std::size_t size) : data_(data), size_(size) {}

  const std::byte* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace gazedirector
