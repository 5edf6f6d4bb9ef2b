// tests/experiments/test_experiment.cpp — `mwst experiment` (src/cli/cmd_experiment.cpp and experiment_*.cpp),
// run as a real process on a tiny data directory (a 30-point polygon and a 40-point cloud):
//   - table1.csv has the documented header and one row per data set; DT is exactly 100 (by
//     construction); every weight is a finite number (no cell is NA for these inputs);
//   - table1.md sets the paper's figures beside ours; runs.csv lists every run;
//   - the results (tables, Figure 3 data, Figure 4 PNGs) do not depend on the number of threads;
//   - a non-default --opt-trials is stated in table1.md (the tests use 10 trials per start: the
//     default search is most of an `experiment` run's time, and test_optimize.cpp tests it);
//   - `all` writes figure3.csv (both Steiner rules, 0°–20°), figure3.gp (and the plots if gnuplot is
//     installed) and the Figure 4 pictures;
//   - no data set is bad input (exit 1), an unknown target bad usage (exit 2).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_bytes(const fs::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary);
  out << content;
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, sep)) fields.push_back(field);
  if (!line.empty() && line.back() == sep) fields.emplace_back();
  return fields;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

bool is_number(const std::string& s, double* value) {
  if (s.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size()) return false;
  *value = v;
  return true;
}

struct Outcome {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// A temporary directory holding data/ (two tiny data sets) and the run's outputs.
class Workspace {
 public:
  Workspace() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::path(testing::TempDir()) /
            ("mwst_experiment_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "data");
    fs::copy_file(fs::path(MWST_DATA_DIR) / "Airliner.poly", root_ / "data" / "Airliner.poly");
    // 40 points from a fixed linear congruential generator, 0-based like Triangle allows.
    std::ostringstream node;
    node << "# cloud.node: 40 pseudo-random points\n40 2 0 0\n";
    std::uint64_t state = 12345;
    for (int i = 0; i < 40; ++i) {
      double xy[2];
      for (double& c : xy) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        c = static_cast<double>(state >> 11) / 9007199254740992.0;
      }
      node.precision(17);
      node << i << ' ' << xy[0] << ' ' << xy[1] << '\n';
    }
    write_bytes(root_ / "data" / "cloud.node", node.str());
    // A Triangle output beside the inputs is not a data set.
    write_bytes(root_ / "data" / "cloud.1.node", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n");
    fs::create_directories(root_ / "capture");
  }
  ~Workspace() {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  fs::path path(const std::string& name) const { return root_ / name; }

  Outcome run(const std::vector<std::string>& args) const {
    const fs::path out_path = root_ / "capture" / "stdout";
    const fs::path err_path = root_ / "capture" / "stderr";
    std::vector<std::string> storage = {MWST_BINARY};
    storage.insert(storage.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : storage) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string cwd = root_.string();
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int o = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (o < 0 || e < 0 || ::dup2(o, 1) < 0 || ::dup2(e, 2) < 0 || ::chdir(cwd.c_str()) != 0) ::_exit(127);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    Outcome r;
    int status = 0;
    if (pid > 0 && ::waitpid(pid, &status, 0) == pid && WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
    r.out = read_bytes(out_path);
    r.err = read_bytes(err_path);
    return r;
  }

 private:
  fs::path root_;
};

std::string describe(const Outcome& r) {
  return "exit " + std::to_string(r.exit_code) + "\n--- stdout:\n" + r.out + "--- stderr:\n" + r.err;
}

bool has_signature(const fs::path& path, const std::string& signature) {
  return read_bytes(path).substr(0, signature.size()) == signature;
}

const std::string kPng("\x89PNG\r\n\x1a\n", 8);

TEST(ExperimentTable1, OneRowPerDataSetDtIsExactly100AndEveryWeightFinite) {
  Workspace w;
  const Outcome r =
      w.run({"experiment", "table1", "--data", "data", "--out", "out", "--jobs", "2", "--opt-trials", "10"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_NE(r.err.find("mwst: experiment: "), std::string::npos) << "progress lines on stderr";

  const std::vector<std::string> lines = lines_of(read_bytes(w.path("out/table1.csv")));
  ASSERT_EQ(lines.size(), 3u) << "header + one row per data set";
  EXPECT_EQ(lines[0].rfind("name,points,segments,boundary,DT,QTR,DR,BRH,BRH+EFH,", 0), 0u) << lines[0];
  const std::vector<std::string> header = split(lines[0], ',');
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  for (const char* name : {"OPT", "steiner_DR", "bundle_DT", "dr_angle", "brh_k"}) {
    EXPECT_TRUE(col.contains(name)) << "missing column " << name;
  }

  std::vector<std::string> names;
  for (std::size_t row = 1; row < lines.size(); ++row) {
    const std::vector<std::string> f = split(lines[row], ',');
    ASSERT_EQ(f.size(), header.size()) << lines[row];
    names.push_back(f[0]);
    double dt = 0.0;
    ASSERT_TRUE(is_number(f[col["DT"]], &dt)) << lines[row];
    EXPECT_EQ(dt, 100.0) << "DT is the normaliser: exactly 100";
    for (const char* c : {"boundary", "QTR", "DR", "BRH", "BRH+EFH", "OPT"}) {
      double v = 0.0;
      ASSERT_TRUE(is_number(f[col[c]], &v)) << c << " in " << lines[row] << " (no cell is NA for these inputs)";
      EXPECT_TRUE(std::isfinite(v) && v > 0.0) << c << " = " << v;
    }
    // OPT searches from BRH+EFH at the setting chosen for BRH+EFH (among other starts) and never
    // returns a heavier mesh than its best start.
    double opt = 0.0, efh = 0.0;
    ASSERT_TRUE(is_number(f[col["OPT"]], &opt) && is_number(f[col["BRH+EFH"]], &efh));
    EXPECT_LE(opt, efh) << lines[row];
    double steiner = 0.0;
    ASSERT_TRUE(is_number(f[col["steiner_DR"]], &steiner));
    EXPECT_EQ(steiner, std::floor(steiner));
    double angle = 0.0;
    ASSERT_TRUE(is_number(f[col["dr_angle"]], &angle));
    EXPECT_GE(angle, 1.0);
    EXPECT_LE(angle, 34.0);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"Airliner", "cloud"}));

  // The paper's figures beside ours; every run listed.
  const std::string md = read_bytes(w.path("out/table1.md"));
  EXPECT_NE(md.find("Airliner (Boeing)"), std::string::npos);
  EXPECT_NE(md.find(" / 256.3 "), std::string::npos) << "the paper's QTR figure for Boeing";
  EXPECT_NE(md.find("searched with --opt-trials 10 trials, not the default"), std::string::npos)
      << "a non-default OPT effort is stated beside the table";
  const std::vector<std::string> runs = lines_of(read_bytes(w.path("out/runs.csv")));
  ASSERT_GT(runs.size(), 2u * 68u) << "DR alone sweeps 34 angles x 2 rules per data set";
  EXPECT_EQ(runs[0].rfind("phase,name,method,", 0), 0u);
}

// Figure 3 and Figure 4 as `experiment all` writes them into `out`.
void expect_figures(const Workspace& w, const std::string& out) {
  for (const char* name : {"table1.csv", "table1.md", "runs.csv", "figure3.csv", "figure3.gp"}) {
    EXPECT_TRUE(fs::exists(w.path(out) / name)) << name;
  }
  // figure3.csv: 2 data sets x 2 rules x 21 angles, every weight a number.
  const std::vector<std::string> f3 = lines_of(read_bytes(w.path(out) / "figure3.csv"));
  ASSERT_EQ(f3.size(), 1u + 2u * 2u * 21u);
  EXPECT_EQ(f3[0], "name,angle,rule,weight,steiner,min_angle,stop_reason");
  std::map<std::string, int> per_rule;
  for (std::size_t i = 1; i < f3.size(); ++i) {
    const std::vector<std::string> f = split(f3[i], ',');
    ASSERT_GE(f.size(), 4u);
    ++per_rule[f[2]];
    double v = 0.0;
    EXPECT_TRUE(is_number(f[3], &v) && std::isfinite(v)) << f3[i];
    if (f[1] == "0") {
      EXPECT_NEAR(v, 100.0, 1e-9) << "no angle bound: DR is DT";
    }
  }
  EXPECT_EQ(per_rule["circumcenter"], 42);
  EXPECT_EQ(per_rule["offcenter"], 42);
  if (fs::exists("/usr/bin/gnuplot")) {
    EXPECT_TRUE(has_signature(w.path(out) / "figure3_cloud.png", kPng));
    EXPECT_TRUE(has_signature(w.path(out) / "figure3_all.pdf", "%PDF-"));
  }
  for (const char* name : {"Airliner", "cloud"}) {
    EXPECT_TRUE(has_signature(w.path(out) / ("figure4_" + std::string(name) + ".png"), kPng)) << name;
    EXPECT_TRUE(has_signature(w.path(out) / ("figure4_" + std::string(name) + ".pdf"), "%PDF-")) << name;
  }
}

// One test for both (each `experiment all` run is the costliest part of the suite, seven times
// slower under the sanitizers): the figures are checked on the one-thread run, and the three-thread
// run must give the same files.
TEST(ExperimentAll, WritesFigure3AndFigure4AndResultsDoNotDependOnTheNumberOfThreads) {
  Workspace w;
  const Outcome one =
      w.run({"experiment", "all", "--data", "data", "--out", "one", "--jobs", "1", "--opt-trials", "10"});
  ASSERT_EQ(one.exit_code, 0) << describe(one);
  expect_figures(w, "one");
  const Outcome two =
      w.run({"experiment", "all", "--data", "data", "--out", "two", "--jobs", "3", "--opt-trials", "10"});
  ASSERT_EQ(two.exit_code, 0) << describe(two);
  // Byte for byte (PDFs carry their creation date, runs.csv the run times: not compared).
  for (const char* name : {"table1.csv", "table1.md", "figure3.csv", "figure3.gp", "figure4_Airliner.png",
                           "figure4_cloud.png"}) {
    const std::string a = read_bytes(w.path("one") / name);
    EXPECT_FALSE(a.empty()) << name;
    EXPECT_TRUE(a == read_bytes(w.path("two") / name)) << name << " differs between 1 and 3 threads";
  }
  EXPECT_EQ(one.out, two.out);
}

TEST(ExperimentCommand, BadDataIsBadInputAndAnUnknownTargetBadUsage) {
  Workspace w;
  fs::create_directories(w.path("empty"));
  const Outcome none = w.run({"experiment", "table1", "--data", "empty", "--out", "out"});
  EXPECT_EQ(none.exit_code, 1) << describe(none);
  EXPECT_FALSE(fs::exists(w.path("out/table1.csv")));
  const Outcome missing = w.run({"experiment", "table1", "--data", "no-such-dir", "--out", "out"});
  EXPECT_EQ(missing.exit_code, 1) << describe(missing);
  const Outcome bad = w.run({"experiment", "table2", "--data", "data", "--out", "out"});
  EXPECT_EQ(bad.exit_code, 2) << describe(bad);
}

}  // namespace
