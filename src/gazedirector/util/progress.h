#pragma once

#include <string>

#include "gazedirector/util/timer.h"

namespace gazedirector {

// Progress of long work on stderr: a bar with rate and time left on a
// terminal, plain log lines (every 10% or 10 s) otherwise. Silent when quiet.
class Progress {
 public:
  Progress(std::string label, long total, std::string unit = "frames", bool quiet = false);
  ~Progress();

  void Update(long done);
  void Finish();
  double elapsed_s() const { return timer_.Seconds(); }

 private:
  std::string label_;
  std::string unit_;
  long total_;
  bool quiet_;
  bool terminal_;
  bool finished_ = false;
  long done_ = 0;
  double last_draw_s_ = -1;
  int last_decile_ = 0;
  Timer timer_;
};

std::string FormatDuration(double seconds);

}  // namespace gazedirector
