// Helpers shared by the `mwst` subcommands (src/cli/commands.hpp): warnings, Triangle's default
// output prefix, the overwrite guard, and output files that are removed again if a command fails.
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "cli/commands.hpp"
#include "mwst/io/triangle_files.hpp"

namespace mwst::cli {

void warn(std::string_view message) { std::cerr << "mwst: warning: " << message << '\n'; }

std::string with_flag_names(std::string_view message, Spelling spelling) {
  const auto word_char = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  };
  std::string out;
  std::size_t i = 0;
  while (i < message.size()) {
    bool replaced = false;
    if (i == 0 || !word_char(message[i - 1])) {
      for (const FieldFlags& names : kFieldFlags) {
        const std::string_view flag = spelling == Spelling::kTriangulate ? names.triangulate : names.triangle;
        const std::size_t end = i + names.field.size();
        if (flag.empty() || message.substr(i, names.field.size()) != names.field) continue;
        if (end < message.size() && word_char(message[end])) continue;
        out += flag;
        i = end;
        replaced = true;
        break;
      }
    }
    if (!replaced) out += message[i++];
  }
  return out;
}

std::string_view field_of_triangulate_flag(std::string_view flag) {
  for (const FieldFlags& names : kFieldFlags) {
    if (!flag.empty() && names.triangulate == flag) return names.field;
  }
  return {};
}

namespace {

// The value of `s` if all of it is a finite decimal number (std::stod's syntax), else nullopt.
std::optional<double> finite_number(const std::string& s) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

std::string shortest(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

CLI::Validator whole_number() {
  return CLI::Validator(
      [](const std::string& s) -> std::string {
        const bool digits = !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
        if (digits) {
          try {
            (void)std::stoull(s);
            return {};
          } catch (const std::out_of_range&) {
          }
        }
        return "must be a whole number >= 0, found '" + s + "'";
      },
      "NONNEGATIVE");
}

CLI::Validator number_above(double low) {
  return CLI::Validator(
      [low](const std::string& s) -> std::string {
        const std::optional<double> v = finite_number(s);
        if (v && *v > low) return {};
        return "must be a number > " + shortest(low) + ", found '" + s + "'";
      },
      "> " + shortest(low));
}

CLI::Validator number_in(double low, double high) {
  const std::string range = "[" + shortest(low) + ", " + shortest(high) + ")";
  return CLI::Validator(
      [low, high, range](const std::string& s) -> std::string {
        const std::optional<double> v = finite_number(s);
        if (v && *v >= low && *v < high) return {};
        return "must be a number in " + range + ", found '" + s + "'";
      },
      "in " + range);
}

std::string default_prefix(const std::string& input) {
  const std::size_t slash = input.find_last_of('/');
  const std::size_t name_start = slash == std::string::npos ? 0 : slash + 1;
  const std::size_t dot = input.find_last_of('.');
  return next_iteration(dot != std::string::npos && dot > name_start ? input.substr(0, dot) : input);
}

std::string next_iteration(const std::string& stem) {
  const std::size_t slash = stem.find_last_of('/');
  const std::size_t name_start = slash == std::string::npos ? 0 : slash + 1;
  // Triangle's iteration number: "foo.1" → "foo.2".
  const std::size_t last_dot = stem.find_last_of('.');
  if (last_dot != std::string::npos && last_dot > name_start && last_dot + 1 < stem.size()) {
    const std::string digits = stem.substr(last_dot + 1);
    bool all_digits = digits.size() <= 9;
    for (const char c : digits) all_digits = all_digits && std::isdigit(static_cast<unsigned char>(c));
    if (all_digits) return stem.substr(0, last_dot + 1) + std::to_string(std::stol(digits) + 1);
  }
  return stem + ".1";
}

void refuse_overwrite(const std::string& input, const std::string& output) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool same = fs::equivalent(input, output, ec);
  if (!ec && same) throw UsageError("the output " + output + " would overwrite the input " + input);
}

OutputFiles::~OutputFiles() {
  if (committed_) return;
  for (const std::string& path : written_) ::unlink(path.c_str());
}

void OutputFiles::write(const std::string& path, std::string_view content) {
  io::write_file_atomic(path, content);
  written_.push_back(path);
}

void OutputFiles::write_files(const std::string& prefix, const std::vector<io::TriangleFile>& files) {
  io::write_triangle_files(prefix, files);  // removes its own files if it fails half-way
  for (const io::TriangleFile& file : files) written_.push_back(prefix + file.extension);
}

void OutputFiles::write_mesh(const MeshArrays& mesh, const std::string& prefix, int first_index,
                             const std::vector<Point>& holes, const std::vector<Region>& regions) {
  const io::TriangleOutput what = io::mesh_files(mesh, first_index);
  write_files(prefix, io::format_triangle_files(mesh, holes, regions, what));
  if (!what.poly) remove_at_commit_.push_back(prefix + ".poly");
}

void OutputFiles::write_json(const std::string& path, const nlohmann::json& json) {
  const std::string text = json.dump(2) + "\n";
  if (path == "-") {
    stdout_text_ += text;
  } else {
    write(path, text);
  }
}

void OutputFiles::commit() {
  for (const std::string& path : remove_at_commit_) ::unlink(path.c_str());
  committed_ = true;
  if (!stdout_text_.empty()) {
    std::cout << stdout_text_;
    std::cout.flush();
  }
}

}  // namespace mwst::cli
