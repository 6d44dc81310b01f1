#pragma once
// Runs the aggpack executable (AGGPACK_EXE) as a user would, capturing what it prints.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace aggpack::testing {

struct CliResult {
  int exit_code;
  std::string output;  // stdout and stderr
};

inline CliResult run_command(const std::string& command) {
  const std::string cmd = command + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

inline CliResult run_cli(const std::string& args) { return run_command(std::string(AGGPACK_EXE) + " " + args); }

// tests/tools/check_outputs.py: the output files read by Python's csv and xml parsers.
inline CliResult check_outputs(const std::string& args) {
  return run_command(std::string(AGGPACK_PYTHON) + " " + std::string(AGGPACK_CHECK_OUTPUTS) + " " + args);
}

// Starts aggpack with `arguments` in a child process (its output discarded), polls `ready`
// every 10 ms until it holds (for `patience` at most), then sends the child `signal_number`
// and waits for it. Returns its exit code (-N when signal N ended it), or nullopt when it
// ended on its own before `ready` held.
inline std::optional<int> signal_aggpack_when(const std::vector<std::string>& arguments,
                                              const std::function<bool()>& ready, int signal_number,
                                              std::chrono::milliseconds patience = std::chrono::minutes(2)) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::freopen("/dev/null", "w", stdout);
    ::freopen("/dev/null", "w", stderr);
    std::vector<char*> argv{const_cast<char*>(AGGPACK_EXE)};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(AGGPACK_EXE, argv.data());
    ::_exit(127);
  }
  int status = 0;
  for (const auto until = std::chrono::steady_clock::now() + patience; std::chrono::steady_clock::now() < until;) {
    if (::waitpid(pid, &status, WNOHANG) == pid) return std::nullopt;
    if (ready()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid, signal_number);
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh folder under the system's temporary directory, named for the test binary's process,
// removed with everything in it when the fixture ends.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& prefix)
      : path_(std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() { std::filesystem::remove_all(path_); }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace aggpack::testing
