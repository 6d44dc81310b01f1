#include "aggpack/run/progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "aggpack/core/text.hpp"

namespace aggpack {

namespace {
constexpr std::chrono::milliseconds kMinInterval{200};
constexpr int kDefaultColumns = 80;
// Erase from the cursor to the end of the line (ANSI, every terminal emulator has it).
constexpr const char* kEraseToEnd = "\033[K";

std::string duration_text(double seconds) {
  if (seconds < 60) return fmt::format("{:.0f} s", std::ceil(seconds));
  if (seconds < 3600) return fmt::format("{:.0f} min {:02.0f} s", std::floor(seconds / 60), std::fmod(seconds, 60));
  return fmt::format("{:.0f} h {:02.0f} min", std::floor(seconds / 3600), std::fmod(seconds, 3600) / 60);
}


std::string truncated(const std::string& s, std::size_t width) {
  if (display_width(s) <= width) return s;
  if (width < 3) return std::string(width, '.');
  std::string out;
  std::size_t n = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if ((c & 0xC0) != 0x80 && ++n > width - 3) break;
    out += s[i];
  }
  return out + "...";
}
}  // namespace

bool Progress::wanted(bool quiet) { return !quiet && isatty(STDERR_FILENO) == 1; }

int Progress::columns() const {
  if (columns_) return *columns_;
  winsize size{};
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
  if (const char* env = std::getenv("COLUMNS")) {
    const int n = std::atoi(env);
    if (n > 0) return n;
  }
  return kDefaultColumns;
}

namespace {
// The middle of `s` cut out to fit `width` characters: a campaign's run name keeps its counter
// and name at the start and its time left in all at the end.
std::string middle_cut(const std::string& s, std::size_t width) {
  if (display_width(s) <= width) return s;
  std::vector<std::string> chars;  // UTF-8 characters
  for (std::size_t i = 0; i < s.size(); ++i) {
    if ((static_cast<unsigned char>(s[i]) & 0xC0) != 0x80) chars.emplace_back();
    if (!chars.empty()) chars.back() += s[i];
  }
  const std::size_t head = (width - 1) / 2, tail = width - 1 - head;
  std::string out;
  for (std::size_t k = 0; k < head; ++k) out += chars[k];
  out += "…";
  for (std::size_t k = chars.size() - tail; k < chars.size(); ++k) out += chars[k];
  return out;
}
}  // namespace

std::string Progress::fit_line(const std::string& run, const std::string& stage,
                               const std::vector<std::string>& fields, const std::string& time_left, int columns) {
  const std::size_t width = static_cast<std::size_t>(std::max(columns - 1, 1));
  const auto compose = [&](const std::string& run_name, std::size_t kept) {
    std::string line = run_name.empty() ? stage : run_name + " | " + stage;
    for (std::size_t k = 0; k < kept; ++k) line += (k == 0 ? ": " : ", ") + fields[k];
    if (!time_left.empty()) line += (kept == 0 ? ": " : ", ") + time_left;
    return line;
  };
  // Details go first, from the end: which run it is, its stage and the time left matter more.
  for (std::size_t kept = fields.size() + 1; kept-- > 0;) {
    const std::string line = compose(run, kept);
    if (display_width(line) <= width) return line;
  }
  // Then the run's name is cut in its middle, down to a dozen characters.
  constexpr std::size_t kShortestRunName = 12;
  const std::size_t rest = display_width(compose("", 0)) + 3;  // " | "
  if (!run.empty() && width >= rest + kShortestRunName) return compose(middle_cut(run, width - rest), 0);
  return truncated(compose("", std::min<std::size_t>(1, fields.size())), width);
}

double Progress::smoothed_time_left(std::optional<double> shown, double seconds_since, double estimate) {
  if (!shown) return estimate;
  const double counted_down = std::max(*shown - seconds_since, 0.0);
  return counted_down + kTimeLeftWeight * (estimate - counted_down);
}

void Progress::start_stage(std::string stage) {
  stage_ = std::move(stage);
  stage_start_ = Clock::now();
  last_print_ = {};
  time_left_.reset();
}

bool Progress::due() const { return (out_ || listener_) && Clock::now() - last_print_ >= kMinInterval; }

void Progress::update(const std::vector<std::string>& fields, double done, TimeLeft kind) {
  if (!due()) return;
  const auto now = Clock::now();
  const double since = last_print_ == Clock::time_point{} ? 0.0 : std::chrono::duration<double>(now - last_print_).count();
  last_print_ = now;
  const double elapsed = std::chrono::duration<double>(now - stage_start_).count();
  std::string time_left;
  if (done > 0.0 && done < 1.0 && elapsed > 1.0) {
    // A bound and an estimate are not averaged together: a change of kind starts afresh.
    if (kind != time_left_kind_) time_left_.reset();
    time_left_kind_ = kind;
    time_left_ = smoothed_time_left(time_left_, since, elapsed * (1.0 - done) / done);
    time_left = fmt::format("{} {} left", kind == TimeLeft::AtMost ? "at most" : "about", duration_text(*time_left_));
  }
  if (listener_) {  // the time left only when this refresh estimated it, as the line shows it
    const std::optional<double> left = time_left.empty() ? std::nullopt : time_left_;
    listener_({run_, stage_, fields, done, left, left && time_left_kind_ == TimeLeft::AtMost});
    return;
  }
  if (left_in_all_)
    time_left += time_left.empty() ? fmt::format("about {} left in all", duration_text(*left_in_all_))
                                   : fmt::format(", {} in all", duration_text(*left_in_all_));
  fmt::print(*out_, "\r{}{}", fit_line(run_, stage_, fields, time_left, columns()), kEraseToEnd);
  out_->flush();
  shown_ = true;
}

void Progress::clear() {
  if (!out_ || !shown_) return;
  fmt::print(*out_, "\r{}", kEraseToEnd);
  out_->flush();
  shown_ = false;
}

}  // namespace aggpack
