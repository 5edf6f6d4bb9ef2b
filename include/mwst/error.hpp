// mwst/error.hpp — typed errors. Nothing below the command line prints or exits; it throws these.
// The command line turns InputError into "mwst: FILE:LINE: what is wrong" and exit code 1.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

#include "mwst/export.hpp"

namespace mwst {

// Bad input: a file that cannot be read or parsed, or a point set / graph we refuse.
// file and line are empty / 0 when the problem is not tied to a place in a file.
class MWST_API InputError : public std::runtime_error {
 public:
  InputError(std::string file, std::size_t line, const std::string& what)
      : std::runtime_error(what), file_(std::move(file)), line_(line) {}
  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }
  // "FILE:LINE: what", "FILE: what" or "what".
  std::string located() const {
    std::string s;
    if (!file_.empty()) {
      s = file_;
      if (line_ > 0) s += ":" + std::to_string(line_);
      s += ": ";
    }
    return s + what();
  }

 private:
  std::string file_;
  std::size_t line_;
};

// A bug: an invariant of ours was broken (exit code 3 at the command line).
class MWST_API InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

}  // namespace mwst
