#include "core/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace granflow {
namespace {
std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--";
  long t = long(s + 0.5);
  char buf[32];
  if (t >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  else std::snprintf(buf, sizeof buf, "%02ld:%02ld", t / 60, t % 60);
  return buf;
}
}  // namespace

Progress::Progress(std::string label, double total, bool quiet)
    : label_(std::move(label)), total_(total), active_(!quiet && isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()), last_draw_(start_ - std::chrono::seconds(1)) {}

Progress::~Progress() {
  if (active_ && !finished_) std::fputs("\n", stderr);
}

void Progress::update(double done, const std::string& status) {
  if (!active_) return;
  auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(200)) return;
  last_draw_ = now;
  double elapsed = std::chrono::duration<double>(now - start_).count();
  double frac = total_ > 0 ? std::clamp(done / total_, 0.0, 1.0) : 0.0;
  double eta = frac > 0 ? elapsed * (1 - frac) / frac : NAN;
  const int width = 24;
  int filled = int(frac * width);
  std::string bar(filled, '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "\r%s [%s] %5.1f%% %s elapsed, ETA %s %s\x1b[K", label_.c_str(), bar.c_str(), 100 * frac,
               format_duration(elapsed).c_str(), format_duration(eta).c_str(), status.c_str());
  std::fflush(stderr);
}

void Progress::finish(const std::string& status) {
  if (!active_ || finished_) return;
  last_draw_ = start_ - std::chrono::seconds(1);
  update(total_, status);
  std::fputs("\n", stderr);
  finished_ = true;
}

}  // namespace granflow
