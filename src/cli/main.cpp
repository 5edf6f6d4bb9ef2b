// The `mwst` command: light Steiner triangulations after Boyacı, Erten, Üngör, "Triangulations
// Loosing Bundles and Weight". Registers the subcommands (src/cli/commands.hpp), parses the command
// line with CLI11, runs the chosen subcommand and turns its errors into the exit codes of the
// contract in DESIGN.md: 0 done, 1 bad input, 2 bad usage, 3 internal error.
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>
#include <new>
#include <stdexcept>
#include <string>

#include "cli/commands.hpp"
#include "mwst/error.hpp"
#include "mwst/version.hpp"

namespace {

using namespace mwst::cli;

// In the order `mwst --help` lists them.
constexpr Registrar kCommands[] = {
    register_triangulate,
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
  } catch (const std::bad_alloc&) {
    std::cerr << "mwst: internal error: out of memory\n";
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
