#include "gazedirector/util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace gazedirector {

std::string FormatDuration(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60) : fmt::format("{}:{:02}", s / 60, s % 60);
}

Progress::Progress(std::string label, long total, std::string unit, bool quiet)
    : label_(std::move(label)), unit_(std::move(unit)), total_(total), quiet_(quiet), terminal_(::isatty(STDERR_FILENO) != 0) {}

Progress::~Progress() {
  if (terminal_ && !quiet_ && !finished_ && last_draw_s_ >= 0) std::fputs("\n", stderr);
}

void Progress::Update(long done) {
  done_ = done;
  if (quiet_) return;
  const double now = timer_.Seconds();
  const double rate = now > 0 ? done / now : 0;
  const double fraction = total_ > 0 ? std::min(1.0, static_cast<double>(done) / total_) : 0;
  const std::string eta = rate > 0 && total_ > 0 ? FormatDuration((total_ - done) / rate) : "?";
  if (terminal_) {
    if (last_draw_s_ >= 0 && now - last_draw_s_ < 0.1 && done < total_) return;
    last_draw_s_ = now;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::fprintf(stderr, "\r%s [%s%s] %ld/%ld %s  %.1f/s  %s left ", label_.c_str(), std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, '.').c_str(), done, total_, unit_.c_str(), rate, eta.c_str());
    std::fflush(stderr);
    return;
  }
  const int decile = static_cast<int>(fraction * 10);
  if (decile > last_decile_ || now - last_draw_s_ >= 10.0) {
    last_decile_ = decile;
    last_draw_s_ = now;
    spdlog::info("{}: {}/{} {} ({:.0f}%), {:.1f}/s, {} left", label_, done, total_, unit_, 100 * fraction, rate, eta);
  }
}

void Progress::Finish() {
  if (finished_) return;
  finished_ = true;
  if (quiet_) return;
  if (terminal_ && last_draw_s_ >= 0) std::fputs("\n", stderr);
  const double seconds = timer_.Seconds();
  spdlog::info("{}: {} {} in {} ({:.1f}/s)", label_, done_, unit_, FormatDuration(seconds), seconds > 0 ? done_ / seconds : 0.0);
}

}  // namespace gazedirector
