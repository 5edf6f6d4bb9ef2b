// The `mwst` command: light Steiner triangulations after Boyacı, Erten, Üngör, "Triangulations
// Loosing Bundles and Weight". Registers the subcommands (src/cli/commands.hpp), parses the command
// line with CLI11, runs the chosen subcommand and turns its errors into the exit codes of the
// contract in docs/DESIGN.md: 0 done, 1 bad input, 2 bad usage, 3 internal error, 4 out of resources
// (memory: the budget of --max-memory, by default 75% of the machine's, ran out, or a request
// cannot fit in it; one line saying so and what to try, and no output files).
//
// The memory budget is the process's address-space limit (limits.cpp), set before anything runs,
// so that a runaway gets std::bad_alloc (caught here) long before the kernel would kill it.
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>
#include <cstdio>
#include <new>
#include <stdexcept>
#include <string>
#include <system_error>

#include "cli/commands.hpp"
#include "mwst/error.hpp"
#include "mwst/version.hpp"
#include "mwst/algorithms/pipeline.hpp"

namespace {

using namespace mwst::cli;

// In the order `mwst --help` lists them.
constexpr Registrar kCommands[] = {
    register_triangulate,
    register_triangle,
    register_check,
    register_generate,
    register_bundle,
    register_draw,
    register_experiment,
};

// Error messages are printed on one line.
std::string one_line(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return s;
}

// Memory ran out: one line, built without the heap that has just run out.
void report_out_of_memory() {
  char budget[64] = "";
  constexpr double kMiB = 1024.0 * 1024.0;
  if (memory_budget() >= 1024.0 * kMiB) {
    std::snprintf(budget, sizeof budget, " of %.3g GiB", memory_budget() / (1024.0 * kMiB));
  } else if (memory_budget() > 0.0) {
    std::snprintf(budget, sizeof budget, " of %.3g MiB", memory_budget() / kMiB);
  }
  std::fprintf(stderr,
               "mwst: out of memory: the run needed more than its memory budget%s (--max-memory); try a "
               "larger --max-area, a --max-steiner or --time-limit, or a larger --max-memory if the machine has it\n",
               budget);
}

int run(const Action& action) {
  try {
    return action();
  } catch (const mwst::InputError& e) {
    std::cerr << "mwst: " << one_line(e.located()) << '\n';
    return kExitBadInput;
  } catch (const UsageError& e) {
    std::cerr << "mwst: " << one_line(e.what()) << '\n';
    return kExitUsage;
  } catch (const std::invalid_argument& e) {
    std::cerr << "mwst: " << one_line(e.what()) << '\n';
    return kExitUsage;
  } catch (const mwst::InternalError& e) {
    std::cerr << "mwst: internal error: " << one_line(e.what()) << '\n';
    return kExitInternal;
  } catch (const mwst::ResourceError& e) {
    std::cerr << "mwst: " << one_line(e.what()) << '\n';
    return kExitResource;
  } catch (const std::bad_alloc&) {
    report_out_of_memory();
    return kExitResource;
  } catch (const std::system_error& e) {
    // A thread that could not be made for want of memory.
    if (e.code() == std::errc::resource_unavailable_try_again || e.code() == std::errc::not_enough_memory) {
      report_out_of_memory();
      return kExitResource;
    }
    std::cerr << "mwst: internal error: " << one_line(e.what()) << '\n';
    return kExitInternal;
  } catch (const std::exception& e) {
    std::cerr << "mwst: internal error: " << one_line(e.what()) << '\n';
    return kExitInternal;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"mwst: light Steiner triangulations (Delaunay, Delaunay refinement, bundle removal, "
               "quadtree refinement, weight optimisation) of Triangle .node/.poly inputs",
               "mwst"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("mwst ") + mwst::kVersionString, "Print the version and exit");
  set_memory_budget(default_memory_budget());
  Action action;
  try {
    for (const Registrar add : kCommands) add(app, action);
  } catch (const std::exception& e) {
    std::cerr << "mwst: internal error: " << one_line(e.what()) << '\n';
    return kExitInternal;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "mwst: " << one_line(e.what()) << '\n'
              << "Run 'mwst --help' or 'mwst COMMAND --help' for the command line.\n";
    return kExitUsage;
  }
  if (!action) {
    std::cerr << "mwst: internal error: the subcommand registered no action\n";
    return kExitInternal;
  }
  return run(action);
}
