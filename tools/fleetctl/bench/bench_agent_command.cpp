// `fleetctl bench agent`: its options; the runs are bench::RunAgentBench (replay) and
// bench::RunLiveAgentBench (live sources), tools/bench/harness/agent.
#include <filesystem>
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/agent/bench_agent.h"
#include "harness/agent/bench_agent_live.h"

namespace fleetloc::fleetctl {

void RegisterBenchAgentCommand(CLI::App& bench, Status* result) {
  auto s = std::make_shared<bench::AgentBenchSettings>();
  s->work_dir = (std::filesystem::temp_directory_path() / "fleetloc-bench-agent").string();
  CLI::App* agent = bench.add_subcommand(
      "agent", "Tracker cycle on the live path (agent over DDS) vs the offline tracker, same run");
  agent->option_defaults()->always_capture_default();
  agent->add_option("--work-dir", s->work_dir, "Mosaic, run, logs");
  agent
      ->add_option("--frames", s->frames,
                   "Frames of the simulated run (--source aravis: 300 unless given)")
      ->check(CLI::Range(10, 100000));
  agent->add_option("--domain", s->domain, "DDS domain")->check(CLI::Range(0, 232));
  agent->add_option("--json", s->json, "Write every number to this JSON file");
  // --source aravis: a live vehicle (fake GigE Vision camera, ROS 2 odometry) instead of a replay.
  auto source = std::make_shared<std::string>("replay");
  auto rate = std::make_shared<double>(10.0);
  agent
      ->add_option("--source", *source,
                   "replay (cycle time, live vs offline), aravis or gstreamer (a live "
                   "fake GigE Vision camera read by the Aravis source or by aravissrc: "
                   "capture -> pose latency, live/offline accuracy)")
      ->check(CLI::IsMember({"replay", "aravis", "gstreamer"}));
  agent->add_option("--rate", *rate, "Camera frame rate, Hz (live sources)")
      ->check(CLI::Range(1.0, 50.0));
  auto extrapolation =
      std::make_shared<double>(bench::LiveAgentBenchSettings().odometry_extrapolation_s);
  agent
      ->add_option(
          "--odometry-extrapolation", *extrapolation,
          "The agent's live.odometry_extrapolation_s (live sources; 0: frames wait for odometry)")
      ->check(CLI::Range(0.0, 0.1));
  auto gst_timestamps =
      std::make_shared<std::string>(bench::LiveAgentBenchSettings().gstreamer_timestamps);
  agent
      ->add_option("--gstreamer-timestamps", *gst_timestamps,
                   "--source gstreamer: device (aravissrc's PTS, the camera's clock) or created "
                   "(aravissrc do-timestamp=true)")
      ->check(CLI::IsMember({"device", "created"}));
  agent->callback([s, source, rate, extrapolation, gst_timestamps, result] {
    if (*source == "replay") return void(*result = bench::RunAgentBench(*s));
    const bool frames_given = s->frames != bench::AgentBenchSettings().frames;
    *result =
        bench::RunLiveAgentBench({s->work_dir, frames_given ? s->frames : 300, *rate, s->domain,
                                  s->json, *source, *extrapolation, *gst_timestamps});
  });
}

}  // namespace fleetloc::fleetctl
