#include "gazedirector/io/text_writer.h"

#include "gazedirector/util/error.h"

namespace gazedirector {

TextWriter::TextWriter(const std::filesystem::path& path, const std::vector<std::filesystem::path>& inputs)
    : output_(path, inputs), stream_(output_.temp_path(), std::ios::binary) {
  if (!stream_) Fail(ExitCode::kOutput, "cannot write {}", path.string());
}

void TextWriter::Finish() {
  stream_.flush();
  if (!stream_.good()) Fail(ExitCode::kOutput, "cannot write {} (disk full?)", output_.path().string());
  stream_.close();
  output_.Commit();
}

CsvWriter::CsvWriter(const std::filesystem::path& path, std::vector<std::string> columns,
                     const std::vector<std::filesystem::path>& inputs)
    : writer_(path, inputs), columns_(columns.size()) {
  AddRow(columns);
}

void CsvWriter::AddRow(const std::vector<std::string>& values) {
  if (values.size() != columns_) Fail(ExitCode::kInternal, "CSV row with {} values for {} columns", values.size(), columns_);
  std::ostream& out = writer_.stream();
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) out << ',';
    out << values[i];
  }
  out << '\n';
}

}  // namespace gazedirector
