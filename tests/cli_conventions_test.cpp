// CLI conventions (issue 22, docs/cli.md): --version on fleetctl and every service, exit status 2
// with one line on stderr for every usage error (the services exited 109 on an unknown flag), and
// "did you mean" for a mistyped fleetctl subcommand.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "cli_runner.h"

namespace fleetloc {
namespace {

using testing::IsBadInput;
using testing::RunCommand;
using testing::RunFleetctl;

const char* const kServices[] = {"map_server", "fleet_supervisor", "tracker_agent"};

std::string Binary(const std::string& name) {
  return std::string(FLEETLOC_BINARY_DIR "/bin/") + name;
}

TEST(CliConventions, VersionOnFleetctlAndEveryService) {
  const testing::CommandResult fleetctl = RunFleetctl("--version");
  EXPECT_EQ(fleetctl.exit_code, 0) << fleetctl.err;
  EXPECT_EQ(fleetctl.out, "fleetctl " FLEETLOC_VERSION "\n");
  for (const char* service : kServices) {
    const testing::CommandResult r = RunCommand(Binary(service) + " --version");
    EXPECT_EQ(r.exit_code, 0) << service << ": " << r.err;
    EXPECT_EQ(r.out, std::string(service) + " " FLEETLOC_VERSION "\n");
  }
}

TEST(CliConventions, EveryUsageErrorExitsTwoWithOneLine) {
  for (const char* service : kServices) {
    EXPECT_TRUE(
        IsBadInput(RunCommand(Binary(service) + " --no-such-flag"), {service, "--no-such-flag"}))
        << service;
    EXPECT_TRUE(IsBadInput(RunCommand(Binary(service) + " --domain"), {service, "--domain"}))
        << service;
  }
  EXPECT_TRUE(IsBadInput(RunFleetctl("--no-such-flag"), {"fleetctl"}));
  EXPECT_TRUE(IsBadInput(RunFleetctl("status --no-such-flag"), {"fleetctl", "--no-such-flag"}));
  EXPECT_TRUE(IsBadInput(RunFleetctl(""), {"fleetctl"}));
  EXPECT_TRUE(IsBadInput(RunFleetctl("track --run"), {"fleetctl", "--run"}));
  EXPECT_TRUE(IsBadInput(RunFleetctl("status --wait abc"), {"fleetctl", "--wait"}));
}

TEST(CliConventions, AMistypedSubcommandGetsADidYouMean) {
  EXPECT_TRUE(
      IsBadInput(RunFleetctl("stauts"), {"unknown command 'stauts'", "did you mean 'status'"}));
  EXPECT_TRUE(IsBadInput(RunFleetctl("mosaic imprt x.png"),
                         {"unknown command 'imprt'", "did you mean 'import'"}));
  // Nothing close: the plain usage error.
  const testing::CommandResult far = RunFleetctl("frobnicate");
  EXPECT_TRUE(IsBadInput(far, {"fleetctl"}));
  EXPECT_EQ(far.err.find("did you mean"), std::string::npos) << far.err;
}

// Every help text names only documents in the repository (issue 22: "CONTRACT §4" pointed at a
// document a user who clones the project cannot read).
TEST(CliConventions, HelpTextsCiteOnlyDocumentsInTheRepository) {
  std::vector<std::string> helps = {"--help"};
  for (const char* sub :
       {"mosaic", "sim", "sim-forward", "track", "remap", "calibrate", "mapmatch", "reloc",
        "status", "compose-floor", "mosaic import", "mosaic build", "mosaic info", "mosaic export",
        "mosaic export-mbtiles", "mosaic prune", "mosaic rollback", "mosaic vehicles"}) {
    helps.push_back(std::string(sub) + " --help");
  }
  std::vector<std::pair<std::string, std::string>> texts;  // (what, help text)
  for (const std::string& help : helps)
    texts.emplace_back("fleetctl " + help, RunFleetctl(help).out);
  for (const char* service : kServices) {
    texts.emplace_back(service, RunCommand(Binary(service) + " --help").out);
  }
  const std::regex doc(R"(docs/[A-Za-z0-9_-]+\.md)");
  int cited = 0;
  for (const auto& [what, text] : texts) {
    EXPECT_FALSE(text.empty()) << what;
    for (const char* outside : {"CONTRACT", "DESIGN"}) {
      EXPECT_EQ(text.find(outside), std::string::npos) << what << " cites " << outside;
    }
    for (std::sregex_iterator m(text.begin(), text.end(), doc), end; m != end; ++m, ++cited) {
      EXPECT_TRUE(std::filesystem::is_regular_file(std::string(FLEETLOC_SOURCE_DIR "/") + m->str()))
          << what << " cites " << m->str() << ", which is not in the repository";
    }
  }
  EXPECT_GE(cited, 3) << "the run-taking commands point to docs/formats.md";
}

}  // namespace
}  // namespace fleetloc
