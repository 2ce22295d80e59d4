#pragma once
// A one-line progress bar on stderr: fraction done, rate, ETA and a free-form status.
// Silent when stderr is not a terminal or when quiet (docs/file-format.md, Messages).
#include <chrono>
#include <string>

namespace granflow {

class Progress {
 public:
  Progress(std::string label, double total, bool quiet);
  ~Progress();
  // done in the same units as total; status is appended (e.g. "ν=0.80 overlap=3e-4").
  void update(double done, const std::string& status = "");
  void finish(const std::string& status = "");
  bool active() const { return active_; }

 private:
  std::string label_;
  double total_;
  bool active_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace granflow
