#include "aggpack/pipeline/progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>
#include <fmt/ostream.h>

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

// Characters, not bytes: a UTF-8 continuation byte does not take a column.
std::size_t display_width(const std::string& s) {
  std::size_t n = 0;
  for (const unsigned char c : s) n += (c & 0xC0) != 0x80;
  return n;
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

std::string Progress::fit_line(const std::string& run, const std::string& stage,
                               const std::vector<std::string>& fields, const std::string& time_left, int columns) {
  const std::size_t width = static_cast<std::size_t>(std::max(columns - 1, 1));
  const auto compose = [&](bool with_run, std::size_t kept) {
    std::string line = with_run && !run.empty() ? run + " | " + stage : stage;
    for (std::size_t k = 0; k < kept; ++k) line += (k == 0 ? ": " : ", ") + fields[k];
    if (!time_left.empty()) line += (kept == 0 ? ": " : ", ") + time_left;
    return line;
  };
  // Drop details from the end, then the run's name; the stage, its first field and the time
  // left go last, cut short if even they do not fit.
  const std::size_t fewest = std::min<std::size_t>(1, fields.size());
  for (const bool with_run : {true, false})
    for (std::size_t kept = fields.size() + 1; kept-- > fewest;) {
      const std::string line = compose(with_run, kept);
      if (display_width(line) <= width) return line;
    }
  return truncated(compose(false, std::min<std::size_t>(1, fields.size())), width);
}

void Progress::start_stage(std::string stage) {
  stage_ = std::move(stage);
  stage_start_ = Clock::now();
  last_print_ = {};
}

bool Progress::due() const { return out_ && Clock::now() - last_print_ >= kMinInterval; }

void Progress::update(const std::vector<std::string>& fields, double done, TimeLeft kind) {
  if (!due()) return;
  const auto now = Clock::now();
  last_print_ = now;
  const double elapsed = std::chrono::duration<double>(now - stage_start_).count();
  std::string time_left;
  if (done > 0.0 && done < 1.0 && elapsed > 1.0)
    time_left = fmt::format("{} {} left", kind == TimeLeft::AtMost ? "at most" : "about",
                            duration_text(elapsed * (1.0 - done) / done));
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
