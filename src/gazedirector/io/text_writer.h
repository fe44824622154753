#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gazedirector/io/atomic_output.h"

namespace gazedirector {

// A text file written through a stream and committed atomically by Finish().
class TextWriter {
 public:
  explicit TextWriter(const std::filesystem::path& path, const std::vector<std::filesystem::path>& inputs = {});
  std::ostream& stream() { return stream_; }
  void Finish();

 private:
  AtomicOutput output_;
  std::ofstream stream_;
};

// Comma-separated values with a header row.
class CsvWriter {
 public:
  CsvWriter(const std::filesystem::path& path, std::vector<std::string> columns,
            const std::vector<std::filesystem::path>& inputs = {});
  void AddRow(const std::vector<std::string>& values);
  void Finish() { writer_.Finish(); }

 private:
  TextWriter writer_;
  std::size_t columns_;
};

}  // namespace gazedirector
