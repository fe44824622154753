#include "cli/analysis_writers.h"

#include <spdlog/spdlog.h>

#include "gazedirector/util/error.h"

namespace gazedirector::cli {

VideoAnalysisWriters::VideoAnalysisWriters(const std::string& input, const VideoInfo& info, const std::string& output,
                                           const std::string& csv, std::vector<std::string> csv_columns,
                                           const std::string& overlay)
    : json_(output, {input}) {
  const std::vector<std::filesystem::path> inputs = {input};
  if (!csv.empty()) csv_.emplace(csv, std::move(csv_columns), inputs);
  if (!overlay.empty()) overlay_.emplace(overlay, WriterOptionsFor(input, info), inputs);
}

void VideoAnalysisWriters::AddCsvRows(const std::vector<std::vector<std::string>>& rows) {
  for (const std::vector<std::string>& row : rows) csv_->AddRow(row);
}

void VideoAnalysisWriters::Finish() {
  json_.Finish();
  if (csv_) csv_->Finish();
  if (overlay_) overlay_->Finish();
}

int NoFaceInVideo(long frames, const std::string& input) {
  spdlog::warn("no face found in any of the {} frames of {}", frames, input);
  return static_cast<int>(ExitCode::kNoFace);
}

}  // namespace gazedirector::cli
