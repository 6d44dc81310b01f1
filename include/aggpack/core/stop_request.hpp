#pragma once
#include <atomic>
#include <stdexcept>
#include <string>

namespace aggpack {

// A request to stop a run at its next safe point (a DEM sample, a deposition progress tick),
// made by SIGINT or SIGTERM through the CLI's signal handler. Lock-free, so a handler may set
// it. The library only reads it: at a safe point, a requested stop throws Interrupted.
class StopRequest {
 public:
  void request(int signal_number) noexcept { signal_.store(signal_number, std::memory_order_relaxed); }
  [[nodiscard]] int signal_number() const noexcept { return signal_.load(std::memory_order_relaxed); }
  [[nodiscard]] bool requested() const noexcept { return signal_number() != 0; }

 private:
  std::atomic<int> signal_{0};
  static_assert(std::atomic<int>::is_always_lock_free);
};

// Thrown at the safe point after a stop was requested; carries the signal and where it stopped.
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal_number, const std::string& where)
      : std::runtime_error("interrupted by signal " + std::to_string(signal_number) + " " + where),
        signal_number_(signal_number), where_(where) {}
  [[nodiscard]] int signal_number() const { return signal_number_; }
  [[nodiscard]] const std::string& where() const { return where_; }

 private:
  int signal_number_;
  std::string where_;
};

// A safe point: throws Interrupted if a stop was requested (`stop` may be null: never).
inline void stop_here_if_requested(const StopRequest* stop, const std::string& where) {
  if (stop && stop->requested()) throw Interrupted(stop->signal_number(), where);
}

}  // namespace aggpack
