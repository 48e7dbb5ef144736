// Fuzz target: the camera files — camera.json (docs/formats.md, with its optional raw block) and
// forward_camera.json (docs/forward_camera.md). Never a crash, whatever the bytes.
#include "fuzz_input.h"
#include "run_io/forward_camera_json.h"
#include "run_io/run.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fleetloc;
  const std::filesystem::path file = fuzz::ScratchDir() / "camera.json";
  fuzz::WriteFile(file, std::string(reinterpret_cast<const char*>(data), size));
  (void)run_io::ReadCameraJson(file);
  (void)run_io::ReadForwardCameraJson(file);
  return 0;
}
