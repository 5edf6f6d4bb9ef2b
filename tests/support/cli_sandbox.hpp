// tests/support/cli_sandbox.hpp — running the `mwst` binary (MWST_BINARY) as a real process in a fresh
// working directory, with its exit code, stdout and stderr captured: shared by tests/cli/test_cli.cpp
// and tests/cli/test_cli_triangle.cpp.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace mwst_cli_test {

namespace fs = std::filesystem;

// ---- running the binary ------------------------------------------------------------------------

struct Outcome {
  int exit_code = -1;
  std::string out;
  std::string err;
  std::vector<std::string> err_lines() const {
    std::vector<std::string> lines;
    std::istringstream in(err);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }
};

inline std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void spit(const fs::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary);
  out << content;
}

// A fresh working directory (where the command runs and writes) and a separate directory for the
// captured stdout/stderr, so that listing the working directory shows only what mwst wrote.
class Sandbox {
 public:
  Sandbox() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "_" + info->name();
    for (char& c : name) {
      if (c == '/') c = '_';
    }
    root_ = fs::path(testing::TempDir()) / ("mwst_cli_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(root_);
    fs::create_directories(root_ / "work");
    fs::create_directories(root_ / "capture");
  }
  ~Sandbox() {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  fs::path dir() const { return root_ / "work"; }
  std::string path(const std::string& name) const { return (dir() / name).string(); }
  void put(const std::string& name, const std::string& content) const { spit(dir() / name, content); }
  std::string get(const std::string& name) const { return slurp(dir() / name); }
  bool has(const std::string& name) const { return fs::exists(dir() / name); }
  std::set<std::string> entries() const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir())) names.insert(e.path().filename().string());
    return names;
  }

  // Runs `mwst args...` with the working directory as current directory.
  Outcome run(const std::vector<std::string>& args) const {
    const std::string out_path = (root_ / "capture" / "stdout").string();
    const std::string err_path = (root_ / "capture" / "stderr").string();
    const std::string work = dir().string();
    std::vector<std::string> argv_storage = {MWST_BINARY};
    argv_storage.insert(argv_storage.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : argv_storage) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int o = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (o < 0 || e < 0 || ::dup2(o, 1) < 0 || ::dup2(e, 2) < 0 || ::chdir(work.c_str()) != 0) ::_exit(127);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    Outcome r;
    int status = 0;
    if (pid > 0 && ::waitpid(pid, &status, 0) == pid && WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
    r.out = slurp(out_path);
    r.err = slurp(err_path);
    return r;
  }

 private:
  fs::path root_;
};

inline std::string describe(const Outcome& r) {
  return "exit " + std::to_string(r.exit_code) + "\n--- stdout:\n" + r.out + "--- stderr:\n" + r.err;
}

inline std::string data(const std::string& name) { return std::string(MWST_DATA_DIR) + "/" + name; }

// Does the binary run under an address-space limit (--max-memory)? Not in sanitizer builds
// (src/cli/limits.cpp sets none there): tests of running out of memory skip.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kAddressLimit = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
inline constexpr bool kAddressLimit = false;
#else
inline constexpr bool kAddressLimit = true;
#endif
#else
inline constexpr bool kAddressLimit = true;
#endif

}  // namespace mwst_cli_test
