#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "gazedirector/io/text_writer.h"
#include "gazedirector/io/video_reader.h"
#include "gazedirector/io/video_writer.h"

namespace gazedirector::cli {

// The CSV rows of one frame: one per item (a face, a fit) by `row`, or a
// single row of none where there is no item, so that every frame shows.
template <typename Item, typename Row>
std::vector<std::vector<std::string>> CsvRows(long frame, double timestamp_s, const std::vector<Item>& items, Row row) {
  std::vector<std::vector<std::string>> rows;
  if (items.empty()) rows.push_back(row(frame, timestamp_s, nullptr));
  for (const Item& item : items) rows.push_back(row(frame, timestamp_s, &item));
  return rows;
}

// What a video's analysis (track, landmarks) writes as it goes: a JSON line a
// frame, and where asked a CSV (CsvRows) and the overlay video. Each stays a
// temporary file until Finish, so that an interrupted run leaves none.
class VideoAnalysisWriters {
 public:
  // `csv` and `overlay` empty: not written.
  VideoAnalysisWriters(const std::string& input, const VideoInfo& info, const std::string& output,
                       const std::string& csv, std::vector<std::string> csv_columns, const std::string& overlay);

  bool writes_csv() const { return csv_.has_value(); }
  bool writes_overlay() const { return overlay_.has_value(); }
  // Each frame: its JSON line, its CSV rows (when writes_csv()) and the
  // frame drawn over (when writes_overlay()).
  void AddLine(const nlohmann::json& line) { json_.stream() << line.dump() << '\n'; }
  void AddCsvRows(const std::vector<std::vector<std::string>>& rows);
  void AddOverlayFrame(const cv::Mat& drawn, double timestamp_s) { overlay_->Write(drawn, timestamp_s); }
  void Finish();

 private:
  TextWriter json_;
  std::optional<CsvWriter> csv_;
  std::optional<VideoWriter> overlay_;
};

// A video none of whose `frames` showed a face: the warning, and the exit code (kNoFace).
int NoFaceInVideo(long frames, const std::string& input);

}  // namespace gazedirector::cli
