#include "aggpack/pipeline/progress.hpp"

#include <cmath>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <unistd.h>

namespace aggpack {

namespace {
constexpr std::chrono::milliseconds kMinInterval{200};

std::string duration_text(double seconds) {
  if (seconds < 60) return fmt::format("{:.0f} s", std::ceil(seconds));
  if (seconds < 3600) return fmt::format("{:.0f} min {:02.0f} s", std::floor(seconds / 60), std::fmod(seconds, 60));
  return fmt::format("{:.0f} h {:02.0f} min", std::floor(seconds / 3600), std::fmod(seconds, 3600) / 60);
}
}  // namespace

bool Progress::wanted(bool quiet) { return !quiet && isatty(STDERR_FILENO) == 1; }

void Progress::start_stage(std::string stage) {
  stage_ = std::move(stage);
  stage_start_ = Clock::now();
  last_print_ = {};
}

void Progress::update(const std::string& detail, double done, bool is_bound) {
  if (!out_) return;
  const auto now = Clock::now();
  if (now - last_print_ < kMinInterval) return;
  last_print_ = now;
  std::string line = fmt::format("{}{}{}: {}", run_, run_.empty() ? "" : " | ", stage_, detail);
  const double elapsed = std::chrono::duration<double>(now - stage_start_).count();
  if (done > 0.0 && done < 1.0 && elapsed > 1.0)
    line += fmt::format(", {}{} left", is_bound ? "at most " : "", duration_text(elapsed * (1.0 - done) / done));
  const std::size_t width = line.size();
  if (width < last_width_) line.append(last_width_ - width, ' ');
  last_width_ = width;
  fmt::print(*out_, "\r{}", line);
  out_->flush();
}

void Progress::clear() {
  if (!out_ || last_width_ == 0) return;
  fmt::print(*out_, "\r{}\r", std::string(last_width_, ' '));
  out_->flush();
  last_width_ = 0;
}

}  // namespace aggpack
