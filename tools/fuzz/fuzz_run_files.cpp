// Fuzz target: a run directory (docs/formats.md) — run.json, camera.json, frames.csv, odometry.csv
// and truth.csv from one input (parts separated by "\n--\n") — read by run_io::ReadRun, and a
// landmark and a points file (docs/formats.md). Any input must give a value or an error, never a
// crash.
#include "fuzz_input.h"
#include "run_io/mapmatch_files.h"
#include "run_io/run.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fleetloc;
  const std::vector<std::string> parts = fuzz::SplitParts(data, size, 5);
  const std::filesystem::path dir = fuzz::ScratchDir();
  const char* names[] = {"run.json", "camera.json", "frames.csv", "odometry.csv", "truth.csv"};
  for (int i = 0; i < 5; ++i) {
    if (!parts[i].empty()) fuzz::WriteFile(dir / names[i], parts[i]);
  }
  (void)run_io::ReadRun(dir);
  (void)run_io::ReadLandmarksCsv(dir / "frames.csv");
  (void)run_io::ReadPointsCsv(dir / "odometry.csv");
  (void)run_io::ReadPosesCsv(dir / "truth.csv");
  return 0;
}
