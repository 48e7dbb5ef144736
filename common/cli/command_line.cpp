// ParseCommandLine: CLI11 errors mapped to the project's exit statuses.
#include "cli/command_line.h"

#include <iostream>
#include <vector>

#include "cli/closest_name.h"

namespace fleetloc::cli {
namespace {

// The first command-line word that names no subcommand where one is expected, with the nearest
// subcommand name; nullopt when every word before the first option is a known subcommand.
std::optional<std::pair<std::string, std::string>> MistypedSubcommand(const CLI::App& app, int argc,
                                                                      char** argv) {
  const CLI::App* level = &app;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') return std::nullopt;
    std::vector<std::string> names;
    const CLI::App* next = nullptr;
    for (const CLI::App* sub : level->get_subcommands([](const CLI::App*) { return true; })) {
      names.push_back(sub->get_name());
      if (sub->get_name() == word) next = sub;
    }
    if (names.empty()) return std::nullopt;  // positional arguments from here on
    if (!next) {
      std::optional<std::string> closest = ClosestName(word, names);
      if (!closest) return std::nullopt;
      return std::make_pair(word, *closest);
    }
    level = next;
  }
  return std::nullopt;
}

}  // namespace

const char* Version() { return FLEETLOC_VERSION; }

void AddVersionFlag(CLI::App& app, const std::string& program) {
  app.set_version_flag("--version", program + " " + Version(), "Print the version and exit");
}

std::optional<int> ParseCommandLine(CLI::App& app, const std::string& program, int argc,
                                    char** argv) {
  AddVersionFlag(app, program);
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    if (auto typo = MistypedSubcommand(app, argc, argv)) {
      std::cerr << program << ": unknown command '" << typo->first << "' (did you mean '"
                << typo->second << "'?); see " << program << " --help\n";
      return 2;
    }
    std::cerr << program << ": " << e.what() << "; see " << program << " --help\n";
    return 2;
  }
}

}  // namespace fleetloc::cli
