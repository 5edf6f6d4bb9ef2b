// tests/test_version.cpp — the version of mwst/version.hpp: it is the CMake project's version
// (MWST_PROJECT_VERSION, passed by tests/CMakeLists.txt), its parts make its string, and it
// reaches the user: `mwst --version`, the JSON report of triangulate() and of `mwst bundle --json`.
#include "mwst/io/report.hpp"
#include "mwst/version.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "mwst/algorithms/pipeline.hpp"

namespace {

namespace fs = std::filesystem;

// Runs a shell command; returns its exit code and stdout.
std::pair<int, std::string> run(const std::string& command) {
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return {-1, ""};
  std::string out;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

TEST(Version, IsTheProjectVersion) {
  EXPECT_STREQ(MWST_VERSION_STRING, MWST_PROJECT_VERSION);
  EXPECT_EQ(std::string(mwst::kVersionString), std::to_string(mwst::kVersionMajor) + "." +
                                                   std::to_string(mwst::kVersionMinor) + "." +
                                                   std::to_string(mwst::kVersionPatch));
  EXPECT_EQ(mwst::kVersionMajor, MWST_VERSION_MAJOR);
  EXPECT_EQ(mwst::kVersionMinor, MWST_VERSION_MINOR);
  EXPECT_EQ(mwst::kVersionPatch, MWST_VERSION_PATCH);
}

TEST(Version, InTheJsonReport) {
  mwst::Pslg input;
  input.points = {{0, 0}, {1, 0}, {0, 1}};
  const nlohmann::json j = mwst::to_json(mwst::triangulate(input, {}));
  ASSERT_TRUE(j.contains("version"));
  EXPECT_EQ(j["version"], mwst::kVersionString);
}

TEST(Version, CommandLine) {
  const auto [code, out] = run(quoted(MWST_BINARY) + " --version");
  EXPECT_EQ(code, 0);
  EXPECT_EQ(out, std::string("mwst ") + mwst::kVersionString + "\n");

  // The reports of `triangulate --json -` and `bundle --json` carry it too.
  const fs::path dir = fs::path(testing::TempDir()) / ("mwst_version_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string input = std::string(MWST_DATA_DIR) + "/Africa.poly";
  const std::string prefix = (dir / "africa").string();
  const auto [tcode, tout] = run(quoted(MWST_BINARY) + " triangulate " + quoted(input) + " -o " + quoted(prefix) +
                                 " --json - --quiet");
  ASSERT_EQ(tcode, 0);
  EXPECT_EQ(nlohmann::json::parse(tout).at("version"), mwst::kVersionString);
  const auto [bcode, bout] = run(quoted(MWST_BINARY) + " bundle " + quoted(input) + " " + quoted(prefix) + " --json");
  ASSERT_EQ(bcode, 0);
  EXPECT_EQ(nlohmann::json::parse(bout).at("version"), mwst::kVersionString);
  fs::remove_all(dir);
}

}  // namespace
